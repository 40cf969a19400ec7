/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_BP_FOCUSER_IMPL_H
#define INCLUDED_NRSAR_BP_FOCUSER_IMPL_H

#include <gnuradio/nrsar/bp_focuser.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include "nonfinite_reporter.h"
#include <array>
#include <limits>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {

class bp_focuser_impl : public bp_focuser
{
private:
    const numerology d_num;
    const geometry d_geo;
    const scene d_scn;
    const bp_config d_cfg;
    const trajectory d_nav;
    const unsigned d_K;
    const double d_ctor_first_range;
    const double d_ctor_range_bin;

    double d_T = 0.0;
    double d_first_range = 0.0;
    double d_range_bin = 0.0;
    unsigned d_M = 0;     // pulses per aperture
    unsigned d_lines = 0; // image lines per aperture: M / cfg.line_step
    long long d_line_shift = 0;
    double d_band_lo_hz = 0.0;
    double d_band_hi_hz = 0.0;
    double d_los_rms = std::numeric_limits<double>::quiet_NaN();
    double d_los_se = std::numeric_limits<double>::quiet_NaN();
    unsigned d_gcp_used = 0;
    static constexpr double s_nan = std::numeric_limits<double>::quiet_NaN();
    std::array<double, 3> d_gcp_offset{ s_nan, s_nan, s_nan }; // NaN: before, or no GCP used
    std::array<double, 3> d_gcp_drift{ s_nan, s_nan, s_nan };
    std::array<double, 4> d_gcp_se{ s_nan, s_nan, s_nan, s_nan };
    std::unique_ptr<kernel::bp_focuser> d_kernel;

    bool d_pending = false; // axis change from a tag, applied at the next aperture
    double d_pending_T = 0.0;
    double d_pending_first_range = 0.0;
    double d_pending_range_bin = 0.0;

    std::vector<gr_complex> d_pulses;             // M x K: the aperture's pulses
    std::vector<std::array<double, 3>> d_antenna; // M: their antenna positions
    unsigned d_fill = 0;
    // The flight's pulse p: slow time d_t0 + (p - d_p0) T, image line d_y0 + (p - d_p0) v T,
    // products (sums of T per pulse drifted 0.19 ms from n T in 1e9 pulses, docs/stress.md);
    // the base moves to the next pulse when T changes.
    std::uint64_t d_pulse = 0; // the flight's index of the next pulse
    std::uint64_t d_p0 = 0;
    double d_t0 = 0.0;
    double d_y0 = 0.0;
    std::vector<gr_complex> d_out; // M / line_step x K image waiting for output
    unsigned d_out_pos = 0;
    unsigned d_out_len = 0;
    double d_out_y0 = 0.0;
    double d_next_y = 0.0; // along-track position of the next aperture's first line
    std::uint64_t d_lines_in = 0;
    std::uint64_t d_apertures = 0;
    bool d_flush_done = false;
    //! cfg.apertures apertures were imaged: nothing more is ingested or emitted.
    bool done() const
    {
        return d_cfg.apertures > 0 && d_apertures_imaged >= d_cfg.apertures;
    }
    std::uint64_t d_apertures_imaged = 0;

    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    std::uint64_t d_nonfinite_pending = 0;

    void configure(double T, double first_range, double range_bin);
    void handle_tag(const tag_t& tag);
    void ingest(const gr_complex* lines, unsigned n);
    void process_aperture();
    int drain(gr_complex* out, int noutput, int produced);

public:
    bp_focuser_impl(const numerology& num,
                    const geometry& geo,
                    const scene& scn,
                    unsigned num_range_bins,
                    double first_range_m,
                    double range_bin_m,
                    const bp_config& cfg,
                    const trajectory& nav);
    ~bp_focuser_impl() override;

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
    bool stop() override;

    bp_config config() const override { return d_cfg; }
    unsigned lines_per_aperture() const override { return d_M; }
    unsigned image_lines_per_aperture() const override { return d_lines; }
    long long line_shift() const override { return d_line_shift; }
    double pulse_interval_s() const override { return d_T; }
    double first_range_m() const override { return d_first_range; }
    double range_bin_m() const override { return d_range_bin; }
    unsigned num_output_bins() const override { return d_K; }
    double band_lo_hz() const override { return d_band_lo_hz; }
    double band_hi_hz() const override { return d_band_hi_hz; }
    bool simd() const override { return d_kernel && d_kernel->simd(); }
    double ground_first_x_m() const override { return d_kernel->grid().first_x_m; }
    double ground_spacing_m() const override { return d_kernel->grid().x_spacing_m; }
    std::uint64_t apertures() const override { return d_apertures - d_cfg.first_aperture; }
    std::uint64_t stream_first_line() const override { return d_cfg.first_aperture * d_M; }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }
    double trajectory_los_rms_m() const override { return d_los_rms; }
    double trajectory_se_m() const override { return d_los_se; }
    unsigned trajectory_gcp_used() const override { return d_gcp_used; }
    std::array<double, 3> trajectory_gcp_offset_m() const override { return d_gcp_offset; }
    std::array<double, 3> trajectory_gcp_drift_mps() const override { return d_gcp_drift; }
    std::array<double, 4> trajectory_gcp_se() const override { return d_gcp_se; }
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_BP_FOCUSER_IMPL_H */
