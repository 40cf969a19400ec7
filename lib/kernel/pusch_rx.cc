/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "pusch_rx_impl.h"
#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/pusch_rx.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
const dmrs_config& checked_dmrs(const numerology& num, const dmrs_config& dmrs)
{
    num.validate();
    dmrs.validate(num);
    if (!dmrs.enabled())
        throw_param("dmrs symbols", 0, "must list at least one DMRS symbol (the receiver "
                                       "estimates the channel from them)");
    check_at_least("num_subcarriers", num.num_subcarriers, 6u);
    return dmrs;
}
} // namespace

namespace pusch_detail {

// Branch-free so that it vectorises for the baseline ISA too.
std::uint32_t equalise_generic(const gr_complex* __restrict y,
                               const gr_complex* __restrict h,
                               float s2,
                               unsigned n,
                               gr_complex* __restrict x,
                               float* __restrict nv,
                               float* __restrict g)
{
    const float* yf = reinterpret_cast<const float*>(y);
    const float* hf = reinterpret_cast<const float*>(h);
    float* xf = reinterpret_cast<float*>(x);
    std::uint32_t bad = 0;
    for (unsigned k = 0; k < n; k++) {
        const float hr = hf[2 * k], hi = hf[2 * k + 1];
        const float gk = std::max(hr * hr + hi * hi, 1e-20f);
        const float inv = 1.0f / gk; // one division per RE
        const float yr = yf[2 * k], yi = yf[2 * k + 1];
        const float xr = (yr * hr + yi * hi) * inv, xi = (yi * hr - yr * hi) * inv;
        const float v = s2 * inv;
        xf[2 * k] = xr;
        xf[2 * k + 1] = xi;
        nv[k] = v;
        g[k] = gk;
        std::uint32_t ur, ui, uv; // exponent all ones: inf or NaN
        std::memcpy(&ur, &xr, 4);
        std::memcpy(&ui, &xi, 4);
        std::memcpy(&uv, &v, 4);
        bad |= static_cast<std::uint32_t>((ur & 0x7f800000u) == 0x7f800000u) |
               static_cast<std::uint32_t>((ui & 0x7f800000u) == 0x7f800000u) |
               static_cast<std::uint32_t>((uv & 0x7f800000u) == 0x7f800000u);
    }
    return bad;
}

} // namespace pusch_detail

// x = y conj(h) / |h|^2 and nv = sigma^2 / |h|^2 for n REs (AVX2 or generic pass, the same
// floats); returns sum |h|^2 (in double). Non-finite results (overflow on garbage input)
// are found by the pass and become erasures.
double pusch_rx::equalise(const gr_complex* y, float s2, unsigned n, gr_complex* x, float* nv)
{
    const gr_complex* h = d_h.data();
    float* g = d_g.data();
    const std::uint32_t bad = d_simd ? pusch_detail::equalise_avx2(y, h, s2, n, x, nv, g)
                                     : pusch_detail::equalise_generic(y, h, s2, n, x, nv, g);
    if (bad)
        for (unsigned k = 0; k < n; k++)
            if (!std::isfinite(x[k].real()) || !std::isfinite(x[k].imag()) || !std::isfinite(nv[k])) {
                // an erasure (LLRs ~ 0), never NaN downstream (found by
                // fuzz_transport_block: NaN reached the hard slicer)
                x[k] = gr_complex(0.0f, 0.0f);
                nv[k] = 1e30f;
            }
    double sum = 0.0; // in RE order, as one loop would
    for (unsigned k = 0; k < n; k++)
        sum += g[k];
    return sum;
}

pusch_rx::pusch_rx(const pusch_config& cfg)
    : d_num(cfg.num),
      d_dmrs(checked_dmrs(cfg.num, cfg.dmrs)),
      d_demapper(cfg.mod),
      d_codec(cfg),
      d_window(cfg.freq_window),
      d_cfg(cfg),
      d_simd(pusch_detail::avx2_available())
{
    const unsigned n = d_num.num_subcarriers;
    for (unsigned l = 0; l < d_num.symbols_per_slot; l++)
        if (!d_dmrs.is_dmrs_symbol(l))
            d_data_symbols.push_back(l);
    d_data_res = d_data_symbols.size() * n;
    for (unsigned s = 0; s < d_num.slots_per_frame; s++)
        for (unsigned l : d_dmrs.symbols)
            d_dmrs_values.push_back(
                dmrs_values(d_dmrs.scrambling_id, s, l, dmrs_count(n)));
    d_h_dmrs.assign(d_dmrs.symbols.size(), std::vector<gr_complex>(n));
    d_ls.resize(dmrs_count(n));
    d_s0.resize(dmrs_count(n) + 1);
    d_s1.resize(dmrs_count(n) + 1);
    d_h.resize(n);
    d_g.resize(n);
    d_x.resize(d_data_res);
    d_nv.resize(d_data_res);
    d_llr.resize(d_data_res * d_demapper.bits_per_symbol());
}

void pusch_rx::set_threads(unsigned threads)
{
    d_codec.set_threads(threads);
    d_threads = threads;
}

void pusch_rx::set_simd(bool allow) { d_simd = allow && pusch_detail::avx2_available(); }

pusch_slot_result pusch_rx::process(const gr_complex* grid, std::uint64_t slot, gr_complex* eq)
{
    pusch_slot_result res;
    const unsigned n = d_num.num_subcarriers;
    const unsigned nd = dmrs_count(n);
    const std::size_t ndm = d_dmrs.symbols.size();
    const std::size_t slot_in_frame = slot % d_num.slots_per_frame;

    // Noise from the empty odd subcarriers of the DMRS symbols.
    double noise = 0.0;
    std::size_t noise_count = 0;
    for (std::size_t j = 0; j < ndm; j++) {
        const gr_complex* y = grid + static_cast<std::size_t>(d_dmrs.symbols[j]) * n;
        for (unsigned k = 1; k < n; k += 2) {
            noise += std::norm(y[k]);
            noise_count++;
        }
    }
    double sigma2 = noise / static_cast<double>(std::max<std::size_t>(noise_count, 1));
    sigma2 = std::max(sigma2, 1e-12);
    res.noise_var = sigma2;

    // LS on the DMRS REs, moving average over d_window of them, odd subcarriers interpolated.
    const int half = static_cast<int>(d_window / 2);
    for (std::size_t j = 0; j < ndm; j++) {
        const gr_complex* y = grid + static_cast<std::size_t>(d_dmrs.symbols[j]) * n;
        const auto& r = d_dmrs_values[slot_in_frame * ndm + j];
        for (unsigned i = 0; i < nd; i++)
            d_ls[i] = y[2 * i] * std::conj(r[i]);
        // Common phase step between neighbouring DMRS REs (a timing offset inside the CP,
        // e.g. ofdm_sync's backoff: exp(-j 2 pi (n - k0) b / F), 0.39 rad per DMRS step at
        // paper). Removed before the fit and the interpolation, put back after: a straight
        // line through rotating phasors shrinks them ((1 + 2 cos phi) / 3 for 3 REs: EVM
        // -24 dB), the midpoint of two as well (cos(phi / 2)).
        std::complex<double> step_sum(0.0, 0.0);
        for (unsigned i = 0; i + 1 < nd; i++)
            step_sum += std::complex<double>(d_ls[i + 1]) * std::conj(std::complex<double>(d_ls[i]));
        double phi = std::arg(step_sum); // rad per DMRS RE (2 subcarriers)
        if (!std::isfinite(phi))
            phi = 0.0;
        if (phi != 0.0) { // exp(-j phi i) by recursion in double (no sincos per RE)
            const std::complex<double> step = std::polar(1.0, -phi);
            std::complex<double> w(1.0, 0.0);
            for (unsigned i = 0; i < nd; i++, w *= step)
                d_ls[i] *= gr_complex(w);
        }
        auto& h = d_h_dmrs[j];
        // Straight-line least-squares fit over a window of d_window DMRS REs, evaluated at
        // i. Inside the band the window is centred (the fit is the moving average); at the
        // edges it is shifted, not shrunk, so the estimate keeps its noise averaging and
        // stays unbiased on a phase slope. Prefix sums of ls(j) and j ls(j) in double.
        d_s0[0] = d_s1[0] = std::complex<double>(0.0, 0.0);
        for (unsigned i = 0; i < nd; i++) {
            const std::complex<double> v(d_ls[i]);
            d_s0[i + 1] = d_s0[i] + v;
            d_s1[i + 1] = d_s1[i] + static_cast<double>(i) * v;
        }
        const int w = static_cast<int>(std::min<unsigned>(d_window, nd));
        const double sxx = w * (static_cast<double>(w) * w - 1.0) / 12.0;
        for (int i = 0; i < static_cast<int>(nd); i++) {
            const int lo = std::max(0, std::min(i - half, static_cast<int>(nd) - w));
            const int hi = lo + w; // exclusive
            const std::complex<double> s0 = d_s0[hi] - d_s0[lo];
            const std::complex<double> s1 = d_s1[hi] - d_s1[lo];
            const double xm = 0.5 * (lo + hi - 1);
            const std::complex<double> mean = s0 / static_cast<double>(w);
            const std::complex<double> slope = sxx > 0 ? (s1 - xm * s0) / sxx : 0.0;
            const std::complex<double> v = mean + slope * (i - xm);
            h[2 * i] = gr_complex(static_cast<float>(v.real()), static_cast<float>(v.imag()));
        }
        // odd subcarriers: linear interpolation; the last one (N even) linear extrapolation
        for (unsigned k = 1; k < n; k += 2)
            h[k] = (k + 1 < n) ? 0.5f * (h[k - 1] + h[k + 1])
                               : h[k - 1] + 0.5f * (h[k - 1] - h[k - 3]);
        if (phi != 0.0) {
            const std::complex<double> step = std::polar(1.0, 0.5 * phi);
            std::complex<double> w(1.0, 0.0);
            for (unsigned k = 0; k < n; k++, w *= step)
                h[k] *= gr_complex(w);
        }
    }

    // Per data symbol: channel in time, equalise, noise variance per RE, EVM.
    double gain = 0.0, evm = 0.0;
    for (std::size_t s = 0; s < d_data_symbols.size(); s++) {
        const unsigned l = d_data_symbols[s];
        const gr_complex* y = grid + static_cast<std::size_t>(l) * n;
        if (ndm == 1) {
            std::copy(d_h_dmrs[0].begin(), d_h_dmrs[0].end(), d_h.begin());
        } else {
            // bracketing pair (extrapolate with the first / last pair outside)
            std::size_t a = 0;
            while (a + 2 < ndm && d_dmrs.symbols[a + 1] < l)
                a++;
            const double la = d_dmrs.symbols[a], lb = d_dmrs.symbols[a + 1];
            const float t = static_cast<float>((l - la) / (lb - la));
            const auto& ha = d_h_dmrs[a];
            const auto& hb = d_h_dmrs[a + 1];
            for (unsigned k = 0; k < n; k++)
                d_h[k] = ha[k] + t * (hb[k] - ha[k]);
        }
        gr_complex* x = d_x.data() + s * n;
        float* nv = d_nv.data() + s * n;
        gain += equalise(y, static_cast<float>(sigma2), n, x, nv);
    }
    // the EVM comes with the LLRs: distance of each RE to its nearest point
    d_demapper.demap(d_x.data(), d_nv.data(), d_data_res, d_llr.data(), &evm);
    const double nre = static_cast<double>(d_data_res);
    res.snr_db = 10.0 * std::log10(std::max(gain / nre / sigma2, 1e-30));
    res.evm_db = 10.0 * std::log10(std::max(evm / nre, 1e-30));
    // The TB's transmissions: repetitions consecutive slots from a multiple of repetitions;
    // each is combined with the ones before it until the TB decodes (HARQ).
    const unsigned pos = static_cast<unsigned>(slot % d_cfg.repetitions);
    if (pos == 0 || slot != d_last_slot + 1) {
        d_done = false;
        d_transmissions = 0;
    }
    d_last_slot = slot;
    res.tb_index = slot / d_cfg.repetitions;
    if (!d_done) {
        res.tb = d_codec.decode(d_llr.data(), d_cfg.rv_of(pos), slot, d_transmissions > 0);
        d_transmissions++;
        res.transmissions = d_transmissions;
        d_done = res.tb.header_ok;
        res.tb_final = d_done || pos + 1 == d_cfg.repetitions;
    }
    if (eq)
        std::copy(d_x.begin(), d_x.end(), eq);
    return res;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
