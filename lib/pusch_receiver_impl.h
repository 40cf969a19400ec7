/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H
#define INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H

#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/pusch_rx.h>
#include <gnuradio/nrsar/pusch_receiver.h>
#include <atomic>
#include <limits>
#include <vector>

namespace gr {
namespace nrsar {

class pusch_receiver_impl : public pusch_receiver
{
private:
    numerology d_num;
    kernel::pusch_rx d_rx;
    std::vector<gr_complex> d_slot_buf; // symbols_per_slot * N
    unsigned d_fill = 0;                // symbols of the current slot buffered
    std::uint64_t d_slot = 0;           // slot index of the buffered slot
    std::vector<gr_complex> d_eq;       // equalised REs not yet written to output 0
    std::size_t d_eq_pos = 0;
    bool d_eq_output = false;
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;

    std::atomic<std::uint64_t> d_ok{ 0 };
    std::atomic<std::uint64_t> d_failed{ 0 };
    std::atomic<std::uint64_t> d_lost{ 0 };
    //! Longest jump in slot numbers whose slots are reported lost one by one (2.4 s at sdr20)
    static constexpr std::uint64_t max_lost_report = 4096;
    bool d_seen_slot_tag = false; // slot numbers are known (a jump in them can be seen)
    bool d_cut = false;           // a gap tag in the slot being buffered
    std::uint64_t d_reported_tb = ~std::uint64_t{ 0 }; // last TB reported on the PDU port
    std::uint64_t d_cut_tb = ~std::uint64_t{ 0 };      // TB of the last slot a gap cut
    std::atomic<std::uint64_t> d_filler{ 0 };
    std::atomic<std::uint64_t> d_bytes{ 0 };
    std::atomic<std::uint64_t> d_partial{ 0 };
    std::atomic<std::uint64_t> d_nonfinite_count{ 0 };
    std::atomic<double> d_snr{ 0.0 };
    std::atomic<double> d_evm{ 0.0 };
    std::atomic<std::uint64_t> d_harq_ok{ 0 };
    std::atomic<std::uint64_t> d_decodes{ 0 };       // decoding attempts
    std::atomic<double> d_iterations_sum{ 0.0 };    // their mean iterations, summed
    unsigned d_repetitions;

    void finish_slot();
    //! The PDU's meta (docs/blocks/pusch_receiver.md); the defaults are a lost TB's.
    struct pdu_meta {
        std::uint64_t slot = 0;
        long seq = -1;
        bool crc_ok = false;
        bool filler = false;
        long payload_len = 0;
        bool pdu_start = false;
        bool pdu_end = false;
        long sn = -1;
        long so = -1;
        bool lost = false;
        long transmissions = 0;
        double ldpc_iterations = 0.0;
        long code_blocks = 0;
        long cb_crc_ok = 0;
        double snr_db = std::numeric_limits<double>::quiet_NaN();
        double evm_db = std::numeric_limits<double>::quiet_NaN();
    };
    void publish(const pdu_meta& m, const pmt::pmt_t& bytes, std::uint64_t tb);
    void report_lost(std::uint64_t slot);

public:
    explicit pusch_receiver_impl(const pusch_config& cfg);

    bool check_topology(int ninputs, int noutputs) override;
    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

    std::uint64_t blocks_ok() const override { return d_ok; }
    std::uint64_t blocks_failed() const override { return d_failed; }
    std::uint64_t blocks_lost() const override { return d_lost; }
    std::uint64_t filler_blocks() const override { return d_filler; }
    std::uint64_t payload_bytes_ok() const override { return d_bytes; }
    double last_snr_db() const override { return d_snr; }
    double last_evm_db() const override { return d_evm; }
    std::uint64_t partial_slots() const override { return d_partial; }
    std::uint64_t nonfinite_samples() const override { return d_nonfinite_count; }
    double code_rate() const override { return d_rx.codec().code_rate(); }
    std::uint64_t payload_bits_per_slot() const override
    {
        return 8 * d_rx.codec().payload_bytes();
    }
    std::uint64_t tbs_bits() const override { return d_rx.codec().tbs_bits(); }
    unsigned code_blocks() const override { return d_rx.codec().code_blocks(); }
    double ldpc_iterations_mean() const override
    {
        return d_decodes ? d_iterations_sum / double(d_decodes) : 0.0;
    }
    std::uint64_t harq_combined_ok() const override { return d_harq_ok; }
    void set_threads(unsigned threads) override
    {
        gr::thread::scoped_lock guard(d_setlock);
        d_rx.set_threads(threads);
    }
    unsigned threads() const override { return d_rx.threads(); }
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_RECEIVER_IMPL_H */
