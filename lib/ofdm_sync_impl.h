/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_SYNC_IMPL_H
#define INCLUDED_NRSAR_OFDM_SYNC_IMPL_H

#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include <gnuradio/nrsar/ofdm_sync.h>

namespace gr {
namespace nrsar {

class ofdm_sync_impl : public ofdm_sync
{
private:
    enum class state { search, drain, track };

    numerology d_num;
    unsigned d_first_dmrs;
    double d_backoff;
    std::int64_t d_backoff_samples;
    kernel::sc_acquirer d_acq;
    kernel::phase_rotator d_rot;
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    state d_state = state::search;
    bool d_reset_pending = false;
    std::uint64_t d_in_origin = 0;  // input item of the acquirer's absolute index 0
    std::uint64_t d_out_origin = 0; // output item of this acquisition's sample 0
    std::int64_t d_next = 0;        // next acquirer-absolute index to output (drain)
    bool d_sync_tag_pending = false;
    std::uint64_t d_next_slot = 0;  // next slot (of this acquisition) to tag
    std::int64_t d_timing = -1;
    std::int64_t d_start = 0;
    double d_cfo_hz = 0.0;
    double d_metric = 0.0;

    void on_lock();
    void tag_slots(std::uint64_t out_begin, std::uint64_t out_end);

public:
    ofdm_sync_impl(const numerology& num, const dmrs_config& dmrs, double threshold, double backoff);

    bool locked() const override { return d_state != state::search; }
    double cfo_hz() const override { return d_cfo_hz; }
    std::int64_t timing_samples() const override { return d_timing; }
    std::int64_t start_samples() const override { return d_start; }
    double metric() const override { return d_metric; }
    double threshold() const override { return d_acq.threshold(); }
    void set_threshold(double threshold) override;
    double backoff() const override { return d_backoff; }
    void reset() override;
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_SYNC_IMPL_H */
