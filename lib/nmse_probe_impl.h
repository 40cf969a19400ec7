/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_NMSE_PROBE_IMPL_H
#define INCLUDED_NRSAR_NMSE_PROBE_IMPL_H

#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <gnuradio/nrsar/nmse_probe.h>
#include <mutex>

namespace gr {
namespace nrsar {

class nmse_probe_impl : public nmse_probe
{
private:
    struct axis {
        double first = 0.0, step = 0.0;
        std::uint64_t count = 0;
        bool known = false;
    };

    // configuration
    const numerology d_num;
    const geometry d_geo;
    const scene d_scene;
    const std::vector<gr_complex> d_constellation;
    filter_type d_filter;
    double d_snr_in_db;
    const unsigned d_vlen;
    const probe_config d_cfg;
    const double d_nm;               // N M
    const double d_subcarriers;      // N
    double d_target_band_hz = 0.0;   // B_target: the reference target's Doppler band

    // state of the aperture being buffered
    kernel::image_metrics d_kernel;
    volk::vector<gr_complex> d_img, d_ref;
    // finish_aperture's noise masks and pixel weights, kept: no allocation per aperture
    std::vector<std::uint8_t> d_bin_mask, d_line_mask;
    std::vector<float> d_weights;
    std::vector<gr::tag_t> d_tags; // work()'s input tags (kept: no allocation per call)
    std::size_t d_lines_in = 0;    // lines buffered
    std::size_t d_capacity = 0;    // lines of the current aperture
    std::uint64_t d_aperture = 0;  // index of the current aperture
    bool d_open = false;           // an aperture is being buffered
    axis d_raxis, d_aaxis;         // latest axes from the tags
    bool d_aaxis_fresh = false;    // d_aaxis came with a tag not yet used by an aperture
    axis d_ap_raxis, d_ap_aaxis;   // axes of the aperture being buffered
    std::uint64_t d_nonfinite_ap = 0;
    std::uint64_t d_skipped = 0;
    bool d_warned_skip = false;

    // results (own lock: getters do not wait for a running computation)
    mutable std::mutex d_result_lock;
    std::map<std::string, double> d_metrics;
    std::uint64_t d_apertures = 0;
    std::uint64_t d_nonfinite = 0;

    void open_aperture(std::uint64_t index);
    void finish_aperture(bool partial);
    double metric(const char* key) const;

public:
    nmse_probe_impl(const numerology& num,
                    const geometry& geo,
                    const scene& scn,
                    const std::vector<gr_complex>& constellation,
                    filter_type filter,
                    double snr_in_db,
                    unsigned vlen,
                    const probe_config& cfg);
    ~nmse_probe_impl() override;

    bool stop() override;

    probe_config config() const override { return d_cfg; }

    void set_snr_in_db(double snr_in_db) override;
    double snr_in_db() const override;
    void set_filter(filter_type filter) override;
    filter_type filter() const override;

    double nmse_db() const override { return metric("nmse_db"); }
    double nmse_theory_db() const override { return metric("nmse_theory_db"); }
    double nmse_theory_band_db() const override { return metric("nmse_theory_band_db"); }
    double pel_db() const override { return metric("pel_db"); }
    double snr_out_db() const override { return metric("snr_out_db"); }
    double islr_db() const override { return metric("islr_db"); }
    double pslr_db() const override { return metric("pslr_db"); }
    double irw_range_m() const override { return metric("irw_range_m"); }
    double irw_azimuth_m() const override { return metric("irw_azimuth_m"); }
    double peak_error_m() const override { return metric("peak_error_m"); }
    std::map<std::string, double> metrics() const override;
    std::uint64_t apertures() const override;
    std::uint64_t nonfinite_count() const override;

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NMSE_PROBE_IMPL_H */
