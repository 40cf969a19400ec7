/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_LMS_PRESUM_H
#define INCLUDED_NRSAR_KERNEL_LMS_PRESUM_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The second paper's LMS presumming baseline [P-3.1, ref. 24]: an adaptive line
 * enhancer per element along azimuth, then keep 1 of D.
 *
 * Per element n (range bin or subcarrier), an L-tap complex predictor estimates pulse m
 * from the L pulses before it and adapts by normalised LMS, minimising the mean-square
 * prediction error E|s(m) - w^H x(m)|^2, x(m) = [s(m-1) .. s(m-L)]:
 *
 *     y(m) = w(m)^H x(m),   e(m) = s(m) - y(m),
 *     w(m+1) = w(m) + mu e(m)^* x(m) / ||x(m)||^2.
 *
 * White noise is unpredictable one pulse ahead, the coherent echo is not, so y(m) is the
 * echo with less noise (Widrow's adaptive line enhancer). No phase compensation: the
 * weights have to learn each bin's Doppler. Output g = D y(g D) (DC gain D, like the other
 * methods), centred on pulse g D; pulses before the stream start count as zero, weights
 * start at zero. Steady-state misadjustment mu / (2 - mu): the output noise of a
 * noise-only element is about that fraction of the input's, and a tone at high SNR comes
 * out with SNR gain 1 / (1 / L + mu / (2 - mu)).
 */
class NRSAR_API lms_presum
{
public:
    //! \param num_bins K elements per pulse; \param decim D >= 1; \param num_taps L >= 1;
    //! \param step normalised step mu in (0, 2).
    lms_presum(unsigned num_bins, unsigned decim, unsigned num_taps, double step);

    /*!
     * Feeds one input pulse (num_bins() samples): predicts it, then adapts. Returns true
     * when the pulse is an output pulse (every D-th, starting with the first), then written
     * to out (num_bins() samples).
     */
    bool push(const gr_complex* in, gr_complex* out);

    unsigned num_bins() const { return d_k; }
    unsigned decim() const { return d_d; }
    unsigned num_taps() const { return d_l; }
    double step() const { return d_mu; }
    //! Current weights of element n, w_j applied to s(m - 1 - j).
    std::vector<gr_complex> weights(unsigned element) const;

private:
    unsigned d_k, d_d, d_l;
    double d_mu;
    unsigned long long d_pushed = 0;
    std::vector<float> d_w;    // L x K complex (re, im interleaved), row j: lag j + 1
    std::vector<float> d_x;    // ring of the last L pulses, L x K complex
    std::vector<float> d_y, d_g, d_nrm;
    unsigned d_head = 0;       // ring row of s(m - 1)
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_LMS_PRESUM_H */
