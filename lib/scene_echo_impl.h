/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_SCENE_ECHO_IMPL_H
#define INCLUDED_NRSAR_SCENE_ECHO_IMPL_H

#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <gnuradio/nrsar/scene_echo.h>

namespace gr {
namespace nrsar {

class scene_echo_impl : public scene_echo
{
private:
    const numerology d_num;
    const geometry d_geo;
    kernel::scene_echo d_echo;
    kernel::gaussian_noise d_noise;
    double d_snr_db;
    double d_variance; //!< sigma^2, 0: no noise
    float d_sigma;     //!< noise standard deviation (E|Z|^2 = sigma^2), 0: no noise
    std::uint64_t d_nonfinite = 0;
    bool d_nonfinite_logged = false;

    void check_and_log(const scene& scn) const;
    void update_sigma();

public:
    scene_echo_impl(const numerology& num,
                    const geometry& geo,
                    const scene& scn,
                    double snr_db,
                    std::uint64_t seed);

    void set_snr_db(double snr_db) override;
    double snr_db() const override;
    double noise_variance() const override;
    void set_scene(const scene& scn) override;
    scene get_scene() const override;
    std::uint64_t nonfinite_count() const override;

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_SCENE_ECHO_IMPL_H */
