/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_DEMOD_IMPL_H
#define INCLUDED_NRSAR_OFDM_DEMOD_IMPL_H

#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include <gnuradio/nrsar/kernel/rx_time_aligner.h>
#include <gnuradio/nrsar/ofdm_demod.h>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {

class ofdm_demod_impl : public ofdm_demod
{
private:
    kernel::ofdm_demodulator d_kernel;
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    const double d_fs;
    const unsigned d_symbols_per_slot;
    const unsigned d_slots_per_frame;
    const pmt::pmt_t d_rx_time_key;

    // rx_time alignment (d_aligner set = on)
    double d_tx_start_time;
    std::unique_ptr<kernel::rx_time_aligner> d_aligner;
    bool d_aligned = false;        // a stamp has fixed d_s0
    std::int64_t d_s0 = 0;         // absolute input sample of TX start (current timeline)
    bool d_reapply = false;        // setter changed T0: recompute from d_s0's stamp
    std::uint64_t d_stamp_abs = 0; // last applied stamp: sample, seconds
    std::uint64_t d_stamp_full = 0;
    double d_stamp_frac = 0.0;
    std::uint64_t d_skip = 0;      // samples still to drop
    std::uint64_t d_next_symbol = 0; // symbol index of the next output item
    std::uint64_t d_fill = 0;        // lost symbols still to output as zeros
    bool d_tag_next = false;       // put a symbol tag on the next output (after a re-alignment)
    std::uint64_t d_lost = 0, d_dropped = 0, d_stamps = 0;
    std::uint64_t d_last_stamp = 0; // input offset of the last stamp counted
    bool d_warned_unstamped = false;
    std::vector<gr::tag_t> d_pending; // tags on dropped samples, for the next output item
    // work()'s tags, rx_time stamps and symbol starts: kept, so no allocation per call
    std::vector<gr::tag_t> d_tags;
    std::vector<std::uint64_t> d_stamps_at;
    std::vector<std::pair<std::uint64_t, int>> d_starts;

    int work_plain(int noutput_items, int ninput, const gr_complex* in, gr_complex* out);
    int work_aligned(int noutput_items, int ninput, const gr_complex* in, gr_complex* out);
    void demod_one(const gr_complex* in, gr_complex* out, std::uint64_t item);
    void apply_stamp(std::uint64_t abs, std::uint64_t full, double frac);
    void apply_offset(std::uint64_t abs, std::int64_t tx_start_offset, const char* why);
    void tag_symbol(std::uint64_t item);
    void count_stamp(std::uint64_t offset);

public:
    ofdm_demod_impl(kernel::ofdm_demodulator&& kern, const numerology& num, double tx_start_time);

    unsigned fft_start() const override { return d_kernel.fft_start(); }
    unsigned symbol_length() const override { return d_kernel.symbol_length(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }

    double tx_start_time() const override { return d_tx_start_time; }
    void set_tx_start_time(double t) override;
    bool aligned() const override { return d_aligned; }
    std::uint64_t next_symbol() const override { return d_next_symbol; }
    std::uint64_t lost_symbols() const override { return d_lost; }
    std::uint64_t dropped_samples() const override { return d_dropped; }
    std::uint64_t rx_time_tags() const override { return d_stamps; }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_DEMOD_IMPL_H */
