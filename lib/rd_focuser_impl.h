/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RD_FOCUSER_IMPL_H
#define INCLUDED_NRSAR_RD_FOCUSER_IMPL_H

#include <gnuradio/nrsar/kernel/fft_size.h>
#include <gnuradio/nrsar/kernel/rd_focuser.h>
#include <gnuradio/nrsar/rd_focuser.h>
#include "nonfinite_reporter.h"
#include <volk/volk_alloc.hh>
#include <memory>

namespace gr {
namespace nrsar {

class rd_focuser_impl : public rd_focuser
{
private:
    const numerology d_num;
    const geometry d_geo;
    const scene d_scn;
    const focuser_config d_cfg;
    const unsigned d_K;
    const double d_ctor_first_range;
    const double d_ctor_range_bin;

    // Current processing parameters.
    double d_T;
    double d_first_range;
    double d_range_bin;
    double d_scene_lo_hz; // scene band with margin
    double d_scene_hi_hz;
    unsigned d_M;
    unsigned d_before;
    unsigned d_after;
    long long d_line_shift = 0; // output window offset from the aperture's pulses [lines]
    std::uint64_t d_skip = 0;   // pulses still to drop before the first block
    std::unique_ptr<kernel::rd_focuser> d_kernel; // built lazily (it owns the FFT plans)

    // Pending changes from tags (applied at the next aperture boundary).
    bool d_pending = false;
    double d_pending_T = 0.0;
    double d_pending_first_range = 0.0;
    double d_pending_range_bin = 0.0;

    volk::vector<gr_complex> d_block; // K x (before + M + after): range-major input lines
    unsigned d_fill = 0;              // lines in d_block
    unsigned d_layout_before = 0;     // history lines d_block was laid out with
    unsigned d_layout_lines = 0;      // lines per range bin (row length) of d_block
    volk::vector<gr_complex> d_out;   // M x K focused lines waiting for output
    unsigned d_out_pos = 0;
    unsigned d_out_len = 0;
    bool d_out_tags_due = false;
    double d_out_y0 = 0.0;
    double d_out_dy = 0.0;

    // Optional range-Doppler map output (port 1): filled only while the port is connected.
    bool d_want_rd = false;
    volk::vector<gr_complex> d_rd; // band bins x K, ascending Doppler
    unsigned d_rd_pos = 0;
    unsigned d_rd_len = 0;
    bool d_rd_tags_due = false;
    double d_rd_f0 = 0.0;
    double d_rd_df = 0.0;
    std::uint64_t d_rd_apertures = 0;

    std::uint64_t d_lines_in = 0;       // input lines ingested
    std::uint64_t d_aperture_start = 0; // absolute line of the next aperture
    std::uint64_t d_apertures = 0;
    double d_next_y = 0.0; // along-track position of the next aperture's first line
    bool d_flush_done = false;

    nonfinite_reporter d_nonfinite;
    std::uint64_t d_nonfinite_pending = 0;

    void configure(double T, double first_range, double range_bin);
    kernel::rd_block make_block() const; // the kernel's block for the current parameters
    void ensure_kernel();
    void ingest(const gr_complex* lines, unsigned n);
    void process_block(); // focus the full block, queue the aperture, shift history
    void handle_tag(const tag_t& tag);
    //! aperture, the given axis tuple (first, step, lines) and range_axis on one item.
    void add_aperture_tags(int port,
                           uint64_t item,
                           uint64_t index,
                           const pmt::pmt_t& axis_key,
                           double first,
                           double step,
                           uint64_t lines);
    int drain(gr_complex* out, int noutput, int produced);
    int drain_rd(gr_complex* out, int noutput, int produced);
    bool queues_empty() const
    {
        return d_out_pos >= d_out_len && (!d_want_rd || d_rd_pos >= d_rd_len);
    }

public:
    rd_focuser_impl(const numerology& num,
                    const geometry& geo,
                    const scene& scn,
                    unsigned num_range_bins,
                    double first_range_m,
                    double range_bin_m,
                    const focuser_config& cfg);
    ~rd_focuser_impl() override;

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
    bool stop() override;

    focuser_config config() const override { return d_cfg; }
    unsigned lines_per_aperture() const override;
    unsigned overlap_before() const override;
    unsigned overlap_after() const override;
    long long line_shift() const override;
    unsigned fft_size() const override;
    double pulse_interval_s() const override;
    double first_range_m() const override;
    double range_bin_m() const override;
    unsigned num_output_bins() const override;
    void copy_inner(gr_complex* dst, const gr_complex* src, unsigned lines) const; // guard
    double band_lo_hz() const override;
    double band_hi_hz() const override;
    unsigned band_bins() const override;
    double max_migration_bins() const override;
    bool rcmc_applied() const override;
    std::uint64_t apertures() const override;
    std::uint64_t nonfinite_count() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RD_FOCUSER_IMPL_H */
