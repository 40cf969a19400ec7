/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RD_FOCUSER_IMPL_H
#define INCLUDED_NRSAR_RD_FOCUSER_IMPL_H

#include <gnuradio/nrsar/kernel/aperture_focuser.h>
#include <gnuradio/nrsar/rd_focuser.h>
#include "nonfinite_reporter.h"

namespace gr {
namespace nrsar {

class rd_focuser_impl : public rd_focuser
{
private:
    const unsigned d_K;
    const double d_ctor_first_range;
    const double d_ctor_range_bin;
    kernel::aperture_focuser d_focuser; // buffering, overlap-save layout and focusing

    // The last aperture's lines waiting for output (port 0) and its map (port 1, filled
    // only while the port is connected).
    unsigned d_out_pos = 0;
    unsigned d_out_len = 0;
    bool d_want_rd = false;
    unsigned d_rd_pos = 0;
    unsigned d_rd_len = 0;
    std::uint64_t d_apertures = 0; // apertures tagged on port 0
    std::uint64_t d_rd_apertures = 0;
    bool d_flush_done = false;

    nonfinite_reporter d_nonfinite;
    std::uint64_t d_nonfinite_pending = 0;
    std::vector<gr::tag_t> d_tags; // work()'s input tags (kept: no allocation per call)

    void log_warnings();
    void prepare(); // the kernel's, logging its warnings
    void ingest(const gr_complex* lines, unsigned n);
    void focus(); // the next aperture, queued for output
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
                    const focuser_config& cfg,
                    const trajectory& nav);
    ~rd_focuser_impl() override;

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
    bool stop() override;

    focuser_config config() const override { return d_focuser.config(); }
    unsigned lines_per_aperture() const override;
    unsigned overlap_before() const override;
    unsigned overlap_after() const override;
    long long line_shift() const override;
    unsigned fft_size() const override;
    double pulse_interval_s() const override;
    double first_range_m() const override;
    double range_bin_m() const override;
    unsigned num_output_bins() const override;
    double band_lo_hz() const override;
    double band_hi_hz() const override;
    unsigned band_bins() const override;
    double max_migration_bins() const override;
    bool rcmc_applied() const override;
    std::uint64_t apertures() const override;
    std::uint64_t nonfinite_count() const override;
    std::uint64_t stream_first_line() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RD_FOCUSER_IMPL_H */
