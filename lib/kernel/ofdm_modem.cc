/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "rx_front_impl.h"
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
void check_layout(unsigned n, unsigned fft_size, unsigned cp, unsigned k0)
{
    check_at_least("num_subcarriers", n, 1u);
    check_at_least("fft_size", fft_size, n);
    if (k0 >= n && n > 0)
        throw_param("k0", k0, "must be below num_subcarriers = " + std::to_string(n));
    if (cp > fft_size)
        throw_param("cp_samples", cp, "must be at most fft_size = " + std::to_string(fft_size));
}
} // namespace

ofdm_modulator::ofdm_modulator(unsigned n, unsigned fft_size, unsigned cp, unsigned k0)
    : d_n(n), d_fft_size(fft_size), d_cp(cp), d_k0(k0)
{
    check_layout(n, fft_size, cp, k0);
    d_scale = float(1.0 / std::sqrt(double(fft_size)));
    d_fft = make_fft_rev(int(fft_size), 1);
    // The bins between N - k0 and fft_size - k0 stay empty: execute() writes only the
    // N used bins and the out-of-place plan preserves its input.
    std::fill_n(d_fft->get_inbuf(), fft_size, gr_complex(0.0f, 0.0f));
}

void ofdm_modulator::execute(const gr_complex* in, gr_complex* out)
{
    gr_complex* bins = d_fft->get_inbuf();
    // Subcarrier n -> bin (n - k0) mod fft_size: n >= k0 to the positive bins, n < k0
    // to the top (negative-frequency) bins.
    std::memcpy(bins, in + d_k0, sizeof(gr_complex) * (d_n - d_k0));
    std::memcpy(bins + d_fft_size - d_k0, in, sizeof(gr_complex) * d_k0);
    d_fft->execute();
    const gr_complex* x = d_fft->get_outbuf();
    // Unitary 1/sqrt(fft_size) on the real and imaginary parts (one float multiply each).
    volk_32f_s32f_multiply_32f(reinterpret_cast<float*>(out + d_cp),
                               reinterpret_cast<const float*>(x),
                               d_scale,
                               2 * d_fft_size);
    std::memcpy(out, out + d_fft_size, sizeof(gr_complex) * d_cp); // cyclic prefix
}

ofdm_demodulator::ofdm_demodulator(
    unsigned n, unsigned fft_size, unsigned cp, unsigned k0, unsigned fft_start)
    : d_n(n), d_fft_size(fft_size), d_cp(cp), d_k0(k0), d_fft_start(fft_start)
{
    check_layout(n, fft_size, cp, k0);
    if (fft_start > cp)
        throw_param("fft_start",
                    fft_start,
                    "must be at most cp_samples = " + std::to_string(cp) +
                        " (a later FFT window reaches into the next symbol)");
    d_scale = float(1.0 / std::sqrt(double(fft_size)));
    d_fft = make_fft_fwd(int(fft_size), 1);
}

void ofdm_demodulator::execute(const gr_complex* in, gr_complex* out)
{
    std::memcpy(d_fft->get_inbuf(), in + d_fft_start, sizeof(gr_complex) * d_fft_size);
    transform(out);
}

bool ofdm_demodulator::execute_if_finite(const gr_complex* in, gr_complex* out)
{
    // A NaN or Inf anywhere in the symbol (the cyclic prefix outside the window too, as
    // finite_guard counts it) makes the sum non-finite. Measured: docs/performance.md.
    float sum = rx_front::copy_pass(in + d_fft_start, d_fft->get_inbuf(), d_fft_size);
    float rest = 0.0f;
    volk_32f_accumulator_s32f(&rest, reinterpret_cast<const float*>(in), 2 * d_fft_start);
    sum += rest;
    const unsigned tail = d_fft_start + d_fft_size;
    rest = 0.0f;
    volk_32f_accumulator_s32f(
        &rest, reinterpret_cast<const float*>(in + tail), 2 * (symbol_length() - tail));
    sum += rest;
    if (!std::isfinite(sum))
        return false;
    transform(out);
    return true;
}

void ofdm_demodulator::transform(gr_complex* out)
{
    d_fft->execute();
    const gr_complex* bins = d_fft->get_outbuf();
    volk_32f_s32f_multiply_32f(reinterpret_cast<float*>(out + d_k0),
                               reinterpret_cast<const float*>(bins),
                               d_scale,
                               2 * (d_n - d_k0));
    volk_32f_s32f_multiply_32f(reinterpret_cast<float*>(out),
                               reinterpret_cast<const float*>(bins + d_fft_size - d_k0),
                               d_scale,
                               2 * d_k0);
}

double phase_rotator::phase() const
{
    const double off = double(d_count % block);
    return std::remainder(d_block_phase + 2.0 * M_PI * d_freq * off, 2.0 * M_PI);
}

void phase_rotator::set_phase(double phase)
{
    d_block_phase = std::remainder(phase, 2.0 * M_PI);
    d_count = 0;
    d_table_block = -1;
}

void phase_rotator::set_frequency(double freq)
{
    const double ph = phase();
    d_freq = freq;
    set_phase(ph);
}

void phase_rotator::rotate(const gr_complex* in, gr_complex* out, std::size_t n)
{
    const double step = 2.0 * M_PI * d_freq;
    if (d_table.size() != block)
        d_table.resize(block);
    std::size_t i = 0;
    while (i < n) {
        const auto blk = std::int64_t(d_count / block);
        const std::size_t off = std::size_t(d_count % block);
        if (blk != d_table_block) {
            // Blocks follow one another (d_count only grows): advance the double phase by
            // whole blocks, then the phasors of this block from a fresh float seed.
            if (d_table_block >= 0)
                d_block_phase = std::remainder(
                    d_block_phase + step * double(block) * double(blk - d_table_block),
                    2.0 * M_PI);
            const gr_complex inc(float(std::cos(step)), float(std::sin(step)));
            gr_complex ph(float(std::cos(d_block_phase)), float(std::sin(d_block_phase)));
            std::fill(d_table.begin(), d_table.end(), gr_complex(1.0f, 0.0f));
            volk_32fc_s32fc_x2_rotator_32fc(d_table.data(), d_table.data(), inc, &ph, block);
            d_table_block = blk;
        }
        const std::size_t len = std::min(block - off, n - i);
        // Own loop, not VOLK's multiply: its FMA kernel and its scalar tail round
        // differently, so the value of a sample would depend on where the call began.
        const gr_complex* t = d_table.data() + off;
        for (std::size_t k = 0; k < len; k++) {
            const float ar = in[i + k].real(), ai = in[i + k].imag();
            const float br = t[k].real(), bi = t[k].imag();
            out[i + k] = gr_complex(ar * br - ai * bi, ar * bi + ai * br);
        }
        i += len;
        d_count += len;
    }
}

sc_acquirer::sc_acquirer(unsigned fft_size, unsigned cp, double threshold, std::size_t lookback)
    : d_half(fft_size / 2), d_cp(cp), d_threshold(threshold), d_lookback(lookback)
{
    if (fft_size < 4 || fft_size % 2 != 0)
        throw_param("fft_size", fft_size, "must be even and at least 4 (half-symbol repetition)");
    check_finite("threshold", threshold);
    if (!(threshold > 0.0 && threshold < 1.0))
        throw_param("threshold", threshold, "must be in (0, 1)");
}

void sc_acquirer::reset()
{
    d_buf.clear();
    d_base = 0;
    d_pos = 0;
    d_since_recompute = -1;
    d_p = 0.0;
    d_e = 0.0;
    d_collecting = false;
    d_m.clear();
    d_pv.clear();
    d_res = result();
    d_refining = false;
    d_floor = 0;
}

void sc_acquirer::reject()
{
    // Windows start after the rejected one (else its edge's crossing finds it again); the
    // buffer still holds those samples: nothing is discarded while locked.
    d_floor = std::int64_t(d_res.plateau_last) + 1;
    d_pos = std::max(d_first + 1, d_floor);
    d_res = result();
    d_refining = false;
    d_collecting = false;
    d_since_recompute = -1;
}

void sc_acquirer::recompute(std::int64_t d)
{
    const gr_complex* r = d_buf.data() + (d - d_base);
    std::complex<double> p = 0.0;
    double e = 0.0;
    for (unsigned m = 0; m < d_half; m++) {
        p += std::conj(std::complex<double>(r[m])) * std::complex<double>(r[m + d_half]);
        e += std::norm(std::complex<double>(r[m])) +
             std::norm(std::complex<double>(r[m + d_half]));
    }
    d_p = p;
    d_e = e;
    d_since_recompute = 0;
}

void sc_acquirer::discard_before(std::int64_t abs)
{
    if (abs <= d_base)
        return;
    const std::size_t drop = std::min<std::size_t>(std::size_t(abs - d_base), d_buf.size());
    d_buf.erase(d_buf.begin(), d_buf.begin() + drop);
    d_base += std::int64_t(drop);
}

bool sc_acquirer::search(std::int64_t end)
{
    const std::int64_t h = d_half;
    constexpr std::int64_t chunk = 8192;
    while (d_pos + 2 * h <= end) {
        if (d_since_recompute < 0 || d_since_recompute >= (1 << 16)) {
            recompute(d_pos);
            const double half_e = 0.5 * d_e;
            if (half_e > 1e-30 && std::norm(d_p) > d_threshold * half_e * half_e) {
                d_first = d_pos;
                return true;
            }
            d_pos++;
            continue;
        }
        // Positions d_pos .. d_pos + c - 1; the state belongs to d_pos - 1. With
        // q[i] = conj(r[i]) r[i+H] and g[i] = |r[i]|^2 (VOLK, from r = sample d_pos - 1):
        // P(d) = P(d-1) - q[k] + q[k+H], E(d) = E(d-1) - g[k] + g[k+2H], k = d - d_pos.
        const std::int64_t c = std::min({ end - 2 * h + 1 - d_pos,
                                          chunk,
                                          std::int64_t(1 << 16) - d_since_recompute });
        const gr_complex* r = d_buf.data() + (d_pos - 1 - d_base);
        if (d_q.size() < std::size_t(c + h))
            d_q.resize(std::size_t(chunk + h));
        if (d_g.size() < std::size_t(c + 2 * h))
            d_g.resize(std::size_t(chunk + 2 * h));
        volk_32fc_x2_multiply_conjugate_32fc(d_q.data(), r + h, r, unsigned(c + h));
        volk_32fc_magnitude_squared_32f(d_g.data(), r, unsigned(c + 2 * h));
        std::complex<double> p = d_p;
        double e = d_e;
        for (std::int64_t k = 0; k < c; k++) {
            p += std::complex<double>(d_q[k + h]) - std::complex<double>(d_q[k]);
            e += double(d_g[k + 2 * h]) - double(d_g[k]);
            const double half_e = 0.5 * e;
            // M > threshold without a division per sample.
            if (std::norm(p) > d_threshold * half_e * half_e && half_e > 1e-30) {
                d_p = p;
                d_e = e;
                d_pos += k;
                d_since_recompute += k + 1;
                d_first = d_pos;
                return true;
            }
        }
        d_p = p;
        d_e = e;
        d_pos += c;
        d_since_recompute += c;
    }
    return false;
}

bool sc_acquirer::push(const gr_complex* in, std::size_t n)
{
    d_buf.insert(d_buf.end(), in, in + n);
    if (d_res.locked)
        return true;
    const std::int64_t end = d_base + std::int64_t(d_buf.size());
    if (d_refining)
        return try_refine(end);
    const std::int64_t h = d_half;
    // After the first threshold crossing, M and P are recomputed and kept from `back`
    // positions before it (a crossing can fall inside the plateau at low SNR) to `ahead`
    // positions after it (rising edge, plateau and falling edge).
    const std::int64_t back = d_cp + d_half / 2;
    const std::int64_t ahead = h + d_cp + h / 2 + 1;
    while (d_pos + 2 * h <= end) {
        if (!d_collecting) {
            if (!search(end))
                break;
            d_collecting = true;
            d_pos = std::max(d_first - back, d_base);
            d_since_recompute = -1;
            d_m.clear();
            d_pv.clear();
            d_m_start = d_pos;
            continue;
        }
        // State (d_p, d_e) belongs to position d_pos - 1 after the first step.
        if (d_since_recompute < 0 || d_since_recompute >= (1 << 16)) {
            recompute(d_pos);
        } else {
            const gr_complex* r = d_buf.data() + (d_pos - 1 - d_base);
            const std::complex<double> a0(r[0]), ah(r[h]), a2h(r[2 * h]);
            d_p += std::conj(ah) * a2h - std::conj(a0) * ah;
            d_e += std::norm(a2h) - std::norm(a0);
            d_since_recompute++;
        }
        const double half_e = 0.5 * d_e;
        d_m.push_back(half_e > 1e-30 ? std::norm(d_p) / (half_e * half_e) : 0.0);
        d_pv.push_back(d_p);
        d_pos++;
        if (d_pos - d_first >= ahead) {
            finish();
            d_refining = true;
            return try_refine(end);
        }
    }
    // Bounded memory: keep lookback (at least back + 1) samples before the oldest position
    // still needed.
    const std::int64_t oldest = d_collecting ? d_m_start : d_pos;
    const std::int64_t keep_from =
        oldest - 1 - std::max<std::int64_t>(std::int64_t(d_lookback), back + 1);
    if (keep_from - d_base > std::int64_t(1 << 16) &&
        keep_from - d_base > std::int64_t(d_buf.size() / 2))
        discard_before(keep_from);
    return false;
}

void sc_acquirer::finish()
{
    // The plateau [d0 + D, d0 + cp] is found as the window of cp + 1 positions with the
    // largest sum of M (a matched filter to the plateau, robust at low SNR where single
    // values of M fluctuate); with symmetric edges the best window starts at d0 + D/2.
    const std::size_t size = d_m.size();
    const std::size_t w = std::min<std::size_t>(d_cp + 1, size);
    const std::size_t from = std::size_t(std::max<std::int64_t>(
        0, std::max(d_first - std::int64_t(d_cp + d_half / 2), d_floor) - d_m_start));
    double sum = 0.0;
    for (std::size_t i = from; i < from + w; i++)
        sum += d_m[i];
    double best = sum;
    std::size_t jbest = from;
    for (std::size_t j = from + 1; j + w <= size; j++) {
        sum += d_m[j + w - 1] - d_m[j - 1];
        if (sum > best) {
            best = sum;
            jbest = j;
        }
    }
    // CFO: P over the middle half of the window (clear of the edges, where neighbouring data
    // symbols mix in when the delay spread shifts the window).
    const std::size_t in_first = jbest + w / 4;
    const std::size_t in_last = jbest + w - 1 - w / 4;
    std::complex<double> psum = 0.0;
    for (std::size_t i = in_first; i <= in_last; i++)
        psum += d_pv[i];
    d_res.metric = *std::max_element(d_m.begin() + jbest, d_m.begin() + jbest + w);
    d_res.plateau_first = double(d_m_start + std::int64_t(jbest));
    d_res.plateau_last = d_res.plateau_first + double(w - 1);
    d_res.symbol_start = d_m_start + std::int64_t(jbest);
    // P's phase is 2 pi CFO H (cycles per sample): fractional CFO, |CFO| < 1/(2H) = Delta f.
    d_res.cfo = std::arg(psum) / (2.0 * M_PI * double(d_half));
    d_psum = psum;
    d_cfo_window = std::int64_t(w);
    d_collecting = false;
    d_m.clear();
    d_m.shrink_to_fit();
    d_pv.clear();
    d_pv.shrink_to_fit();
}

void sc_acquirer::set_repeats(const std::vector<std::int64_t>& offsets)
{
    for (auto o : offsets)
        if (o <= 0)
            throw_param("repeat offset", o, "must be positive");
    d_repeats = offsets;
}

bool sc_acquirer::try_refine(std::int64_t end)
{
    // The same middle half of the plateau window, shifted to each further repeated symbol:
    // P has the same phase 2 pi CFO H there, so the sums add coherently.
    const std::int64_t h = d_half;
    const std::int64_t w = d_cfo_window;
    const std::int64_t first = w / 4, count = w - 2 * (w / 4);
    std::int64_t need = 0;
    for (auto o : d_repeats)
        need = std::max(need, d_res.symbol_start + o + first + count - 1 + 2 * h);
    if (end < need)
        return false;
    std::complex<double> psum = d_psum;
    for (auto o : d_repeats) {
        const gr_complex* r = d_buf.data() + (d_res.symbol_start + o + first - d_base);
        std::complex<double> p = 0.0;
        for (std::int64_t m = 0; m < h; m++)
            p += std::conj(std::complex<double>(r[m])) * std::complex<double>(r[m + h]);
        for (std::int64_t j = 0; j < count; j++) {
            if (j > 0) {
                const std::complex<double> a0(r[j - 1]), ah(r[j - 1 + h]), a2h(r[j - 1 + 2 * h]);
                p += std::conj(ah) * a2h - std::conj(a0) * ah;
            }
            psum += p;
        }
    }
    d_res.cfo = std::arg(psum) / (2.0 * M_PI * double(h));
    d_res.repeats_used = 1 + unsigned(d_repeats.size());
    d_res.locked = true;
    d_refining = false;
    return true;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
