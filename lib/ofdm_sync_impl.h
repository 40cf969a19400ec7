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
#include <gnuradio/nrsar/kernel/sync_tracker.h>
#include <gnuradio/nrsar/ofdm_sync.h>
#include <vector>

namespace gr {
namespace nrsar {

class ofdm_sync_impl : public ofdm_sync
{
private:
    enum class state { search, drain, track };

    numerology d_num;
    unsigned d_first_dmrs;
    unsigned d_num_dmrs;
    double d_backoff;
    std::int64_t d_backoff_samples;
    kernel::sc_acquirer d_acq;
    kernel::phase_rotator d_rot;
    kernel::sync_tracker d_tracker;
    kernel::dmrs_matcher d_matcher;
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    pmt::pmt_t d_rx_time_key;
    state d_state = state::search;
    bool d_reset_pending = false;
    bool d_fresh = true;            // the next lock starts a new grid (stream start, reset)
    std::uint64_t d_in_origin = 0;  // input item of the acquirer's absolute index 0
    std::int64_t d_next = 0;        // next acquirer-absolute index to output (drain)
    bool d_sync_tag_pending = false;
    std::uint64_t d_sync_tag_item = 0;
    // The slot grid (kernel::sync_tracker): input item i is grid sample i - d_grid_start,
    // output item o is grid sample o - d_out_minus_grid.
    std::int64_t d_grid_start = 0;
    std::int64_t d_out_minus_grid = 0;
    std::uint64_t d_grid_out = 0;   // grid sample of the next output item
    std::uint64_t d_next_slot = 0;  // next slot to tag
    // After a gap or a lost lock: zeros owed, input samples to drop, the slot to resume at.
    std::uint64_t d_pad = 0;
    bool d_gap_tag_pending = false; // tags::gap_key() on the first zero of the pad
    std::uint64_t d_gap_samples = 0;
    std::uint64_t d_drop = 0;
    bool d_resume = false;
    std::uint64_t d_resume_slot = 0;
    bool d_search_pending = false;
    // The drained buffer's samples after a lock lost there: the new search's start.
    std::vector<gr_complex> d_rest;
    // The found DMRS symbol's window at a lock, derotated (the slots' checks: d_tracker).
    std::vector<gr_complex> d_check;
    // The last rx_time stamp: input item and time.
    bool d_have_stamp = false;
    std::uint64_t d_stamp_abs = 0;
    std::uint64_t d_stamp_full = 0;
    double d_stamp_frac = 0.0;
    std::int64_t d_timing = -1;
    std::int64_t d_start = 0;
    double d_cfo_hz = 0.0;
    double d_metric = 0.0;
    std::uint64_t d_lost_samples = 0;
    std::uint64_t d_reacquisitions = 0;
    std::uint64_t d_lock_losses = 0;
    std::uint64_t d_skipped_slots = 0;
    std::uint64_t d_skipped_symbols = 0;
    std::uint64_t d_gaps = 0;

    // Takes the acquirer's lock, or rejects it (false): its symbol passed no DMRS test.
    bool on_lock(std::uint64_t out_item);
    // Pushes to the acquirer; takes the first lock that is not rejected.
    void acquire(const gr_complex* x, std::size_t n, std::uint64_t out_item);
    const gr_complex* lock_window(std::int64_t symbol_start, double cfo);
    void tag_slots(std::uint64_t out_begin, std::uint64_t out_end);
    void jump_grid(std::uint64_t to);
    void handle_stamp(const gr::tag_t& tag, std::uint64_t out_item);
    void lose_lock(const char* why);
    //! n output samples (derotated) at d_grid_out to the lock check; true: it lost the lock.
    bool output_checked(const gr_complex* out, std::size_t n);

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
    std::uint64_t lost_samples() const override { return d_lost_samples; }
    std::uint64_t reacquisitions() const override { return d_reacquisitions; }
    std::uint64_t lock_losses() const override { return d_lock_losses; }
    std::uint64_t skipped_slots() const override { return d_skipped_slots; }
    std::uint64_t skipped_symbols() const override { return d_skipped_symbols; }
    std::uint64_t rx_time_gaps() const override { return d_gaps; }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_SYNC_IMPL_H */
