/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_ECHO_NOISE_H
#define INCLUDED_NRSAR_KERNEL_ECHO_NOISE_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The receiver noise of the echo generators (scene_echo, extended_scene_echo,
 * td_echo): the level from the SNR per RE and the scene's power, and the seeded generator.
 *
 * SNR per RE = signal power / sigma^2 (SPEC sections 2 and 3, eq. 7): sigma^2 =
 * signal_power / 10^(snr_db / 10), the signal power being the sum of the targets' RCS (the
 * total scatterer power for an extended scene). snr_db = +inf: no noise (sigma = 0); NaN
 * and -inf are refused. Until set_snr_db() is called there is no noise. In the time domain
 * (td_echo) the unitary FFT of the demodulator maps sigma^2 per sample to sigma^2 per RE.
 */
class NRSAR_API echo_noise
{
public:
    explicit echo_noise(std::uint64_t seed);

    //! Throws std::invalid_argument (naming snr_db) for NaN and -inf.
    void set_snr_db(double snr_db);
    //! The scene's power (sum of RCS), >= 0; e.g. after a scene change.
    void set_signal_power(double signal_power);

    double snr_db() const { return d_snr_db; }
    double signal_power() const { return d_power; }
    //! sigma^2 per RE; 0: no noise.
    double variance() const { return d_variance; }
    //! sigma as the kernels take it (E|Z|^2 = sigma^2).
    float sigma() const { return d_sigma; }
    std::uint64_t seed() const { return d_gen.seed(); }
    //! The generator the echo kernels add the noise with.
    const gaussian_noise* generator() const { return &d_gen; }

private:
    gaussian_noise d_gen;
    double d_snr_db;
    double d_power = 0.0;
    double d_variance = 0.0;
    float d_sigma = 0.0f;

    void update();
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_ECHO_NOISE_H */
