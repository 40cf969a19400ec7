/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/lms_presum.h>
#include <algorithm>
#include <cstddef>

namespace gr {
namespace nrsar {
namespace kernel {

lms_presum::lms_presum(unsigned num_bins, unsigned decim, unsigned num_taps, double step)
    : d_k(num_bins), d_d(decim), d_l(num_taps), d_mu(step)
{
    check_at_least("num_bins", num_bins, 1u);
    check_at_least("decim", decim, 1u);
    check_at_least("num_taps", num_taps, 1u);
    check_finite("lms_step", step);
    if (!(step > 0.0 && step < 2.0))
        throw_param("lms_step", step, "must be in (0, 2) (normalised LMS converges there)");
    const std::size_t n = static_cast<std::size_t>(d_l) * d_k * 2;
    d_w.assign(n, 0.0f);
    d_x.assign(n, 0.0f);
    d_y.assign(2 * static_cast<std::size_t>(d_k), 0.0f);
    d_g.assign(2 * static_cast<std::size_t>(d_k), 0.0f);
    d_nrm.assign(d_k, 0.0f);
}

std::vector<gr_complex> lms_presum::weights(unsigned element) const
{
    std::vector<gr_complex> w(d_l);
    for (unsigned j = 0; j < d_l; ++j) {
        const float* r = d_w.data() + (static_cast<std::size_t>(j) * d_k + element) * 2;
        w[j] = gr_complex(r[0], r[1]);
    }
    return w;
}

bool lms_presum::push(const gr_complex* in, gr_complex* out)
{
    const std::size_t k2 = 2 * static_cast<std::size_t>(d_k);
    float* y = d_y.data();
    float* nrm = d_nrm.data();
    std::fill(d_y.begin(), d_y.end(), 0.0f);
    std::fill(d_nrm.begin(), d_nrm.end(), 0.0f);
    // y = w^H x and ||x||^2 over the L previous pulses (lag j in ring row head + j).
    for (unsigned j = 0; j < d_l; ++j) {
        const float* w = d_w.data() + j * k2;
        const float* x = d_x.data() + ((d_head + j) % d_l) * k2;
        for (unsigned n = 0; n < d_k; ++n) {
            const float wr = w[2 * n], wi = w[2 * n + 1], xr = x[2 * n], xi = x[2 * n + 1];
            y[2 * n] += wr * xr + wi * xi; // conj(w) x
            y[2 * n + 1] += wr * xi - wi * xr;
            nrm[n] += xr * xr + xi * xi;
        }
    }
    const bool emit = d_pushed % d_d == 0;
    const float* s = reinterpret_cast<const float*>(in);
    if (emit) {
        float* o = reinterpret_cast<float*>(out);
        const float gain = static_cast<float>(d_d);
        for (std::size_t i = 0; i < k2; ++i)
            o[i] = gain * y[i];
    }
    // g = mu e^* / ||x||^2 (no update while the history is all zero)
    float* g = d_g.data();
    const float mu = static_cast<float>(d_mu);
    for (unsigned n = 0; n < d_k; ++n) {
        const float c = nrm[n] > 0.0f ? mu / nrm[n] : 0.0f;
        g[2 * n] = c * (s[2 * n] - y[2 * n]);
        g[2 * n + 1] = -c * (s[2 * n + 1] - y[2 * n + 1]);
    }
    // w_j += g x_j
    for (unsigned j = 0; j < d_l; ++j) {
        float* w = d_w.data() + j * k2;
        const float* x = d_x.data() + ((d_head + j) % d_l) * k2;
        for (unsigned n = 0; n < d_k; ++n) {
            const float gr = g[2 * n], gi = g[2 * n + 1], xr = x[2 * n], xi = x[2 * n + 1];
            w[2 * n] += gr * xr - gi * xi;
            w[2 * n + 1] += gr * xi + gi * xr;
        }
    }
    // s(m) becomes lag 0 of the next pulse, over the oldest row
    d_head = (d_head + d_l - 1) % d_l;
    std::copy(s, s + k2, d_x.data() + d_head * k2);
    ++d_pushed;
    return emit;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
