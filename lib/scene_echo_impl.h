/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_SCENE_ECHO_IMPL_H
#define INCLUDED_NRSAR_SCENE_ECHO_IMPL_H

#include <gnuradio/nrsar/kernel/echo_noise.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <gnuradio/nrsar/kernel/split_worker.h>
#include <gnuradio/nrsar/scene_echo.h>
#include "nonfinite_reporter.h"
#include <vector>

namespace gr {
namespace nrsar {

class scene_echo_impl : public scene_echo
{
private:
    const numerology d_num;
    const geometry d_geo;
    kernel::scene_echo d_echo;
    kernel::scene_echo d_echo2; //!< scratch of the second thread (same parameters)
    kernel::echo_noise d_noise; //!< level from the SNR and the scene's RCS, generator
    nonfinite_reporter d_nonfinite;

    std::vector<std::size_t> d_bad; //!< non-finite count per item of one work() call

    // Optional second thread: takes the second half of the items of a work() call.
    unsigned d_threads = 1;
    bool d_reference_only = false;
    kernel::split_worker d_split; // joined in stop() and before the kernels go

    void check_and_log(const scene& scn) const;
    //! Echo of `count` symbols starting at absolute index m0 with kernel k.
    void process(kernel::scene_echo& k,
                 const gr_complex* in,
                 gr_complex* out,
                 gr_complex* ref,
                 std::uint64_t m0,
                 int count,
                 std::size_t* bad);

public:
    scene_echo_impl(const numerology& num,
                    const geometry& geo,
                    const scene& scn,
                    double snr_db,
                    std::uint64_t seed,
                    const trajectory& path);

    void set_snr_db(double snr_db) override;
    double snr_db() const override;
    double noise_variance() const override;
    void set_scene(const scene& scn) override;
    scene get_scene() const override;
    trajectory path() const override { return d_echo.path(); }
    std::uint64_t nonfinite_count() const override;
    void set_threads(unsigned threads) override;
    unsigned threads() const override;
    void set_reference_only(bool on) override;
    bool reference_only() const override;
    bool check_topology(int ninputs, int noutputs) override;

    bool stop() override;
    ~scene_echo_impl() override;

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_SCENE_ECHO_IMPL_H */
