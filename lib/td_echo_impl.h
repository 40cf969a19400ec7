/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TD_ECHO_IMPL_H
#define INCLUDED_NRSAR_TD_ECHO_IMPL_H

#include <gnuradio/nrsar/kernel/echo_noise.h>
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/td_echo.h>
#include <gnuradio/nrsar/td_echo.h>
#include "nonfinite_reporter.h"
#include <volk/volk_alloc.hh>

namespace gr {
namespace nrsar {

class td_echo_impl : public td_echo
{
private:
    const numerology d_num;
    const geometry d_geo;
    kernel::td_echo d_echo;
    kernel::echo_noise d_noise; // level from the SNR and the scene's RCS, generator
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    bool d_dropped_logged = false;
    //! One past the absolute index of the last non-finite input sample (0: none yet).
    std::uint64_t d_bad_end = 0;

    void check_and_log(const scene& scn) const;

public:
    td_echo_impl(const numerology& num,
                 const geometry& geo,
                 const scene& scn,
                 double snr_db,
                 std::uint64_t seed,
                 unsigned taps,
                 double kaiser_beta,
                 const kernel::antenna_beam& beam,
                 const trajectory& path);

    void set_snr_db(double snr_db) override;
    double snr_db() const override { return d_noise.snr_db(); }
    double noise_variance() const override { return d_noise.variance(); }
    void set_scene(const scene& scn) override;
    scene get_scene() const override;
    unsigned taps() const override { return d_echo.fir().taps(); }
    kernel::antenna_beam beam() const override { return d_echo.beam(); }
    trajectory path() const override { return d_echo.path(); }
    double kaiser_beta() const override { return d_echo.fir().beta(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }
    std::uint64_t dropped_paths() const override { return d_echo.dropped_paths(); }

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TD_ECHO_IMPL_H */
