/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_IMPL_H
#define INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_IMPL_H

#include <gnuradio/nrsar/extended_scene_echo.h>
#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/kernel/echo_noise.h>
#include "nonfinite_reporter.h"

namespace gr {
namespace nrsar {

class extended_scene_echo_impl : public extended_scene_echo
{
private:
    const numerology d_num;
    kernel::extended_scene d_gen;
    kernel::echo_noise d_noise; // level from the SNR and the total scatterer power
    nonfinite_reporter d_nonfinite;


public:
    extended_scene_echo_impl(const numerology& num,
                             const geometry& geo,
                             const scene& points,
                             const std::vector<kernel::reflectivity_map>& maps,
                             const kernel::antenna_beam& beam,
                             double snr_db,
                             std::uint64_t seed,
                             unsigned taps,
                             double oversampling,
                             const trajectory& path);

    void set_snr_db(double snr_db) override;
    double snr_db() const override { return d_noise.snr_db(); }
    double noise_variance() const override { return d_noise.variance(); }
    double total_power() const override { return d_gen.total_power(); }
    std::uint64_t num_scatterers() const override { return d_gen.num_scatterers(); }
    unsigned grid_size() const override { return d_gen.grid_size(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_EXTENDED_SCENE_ECHO_IMPL_H */
