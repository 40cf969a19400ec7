/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "nr_ldpc_decoder_impl.h"
#include "param_check.h"
#include <gnuradio/nrsar/kernel/nr_ldpc_decoder.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {
namespace kernel {
namespace ldpc_detail {

template <typename T>
bool layer_generic(T* t, T* r, unsigned deg, unsigned zp, unsigned zc, T offset)
{
    constexpr int hi = fixed<T>::max;
    T min1[lanes], min2[lanes], sgn[lanes], sgnl[lanes];
    bool ok = true;
    for (unsigned v = 0; v < zp; v += lanes) {
        std::fill(min1, min1 + lanes, hi);
        std::fill(min2, min2 + lanes, hi);
        std::fill(sgn, sgn + lanes, 0);
        std::fill(sgnl, sgnl + lanes, 0);
        for (unsigned e = 0; e < deg; e++) {
            T* pt = t + e * zp + v;
            const T* pr = r + e * zp + v;
            for (unsigned z = 0; z < lanes; z++) {
                const auto xs = static_cast<T>(std::clamp(pt[z] - pr[z], -hi, hi));
                const int a = std::abs(xs);
                pt[z] = xs;
                min2[z] = static_cast<T>(std::min<int>(min2[z], std::max<int>(min1[z], a)));
                min1[z] = static_cast<T>(std::min<int>(min1[z], a));
                sgn[z] ^= xs;
            }
        }
        for (unsigned e = 0; e < deg; e++) {
            T* pt = t + e * zp + v;
            T* pr = r + e * zp + v;
            for (unsigned z = 0; z < lanes; z++) {
                const int x = pt[z];
                const int m = std::max((std::abs(x) == min1[z] ? min2[z] : min1[z]) - offset, 0);
                const int s = (sgn[z] ^ x) < 0 ? -m : m;
                pr[z] = static_cast<T>(s);
                pt[z] = static_cast<T>(std::clamp(x + s, -hi, hi));
                sgnl[z] ^= pt[z];
            }
        }
        for (unsigned z = 0; z < lanes && v + z < zc; z++)
            ok = ok && sgnl[z] >= 0;
    }
    return ok;
}

template <typename T>
void quantize_generic(const float* in, unsigned n, float scale, T* out)
{
    constexpr float lim = fixed<T>::in_max;
    for (unsigned k = 0; k < n; k++) {
        const float v = in[k];
        float x = v == v ? v * scale : 0.0f;
        x = std::min(std::max(x, -lim), lim);
        // Adding and removing 1.5 2^23 rounds to nearest even, like cvtps2dq (|x| < 2^22).
        const int q = static_cast<int>((x + 12582912.0f) - 12582912.0f);
        out[k] = static_cast<T>(v == INFINITY ? fixed<T>::max : (v == -INFINITY ? -fixed<T>::max : q));
    }
}

void root_sums_generic(const float* in, std::size_t n8, float* part, float* cnt)
{
    for (std::size_t k = 0; k < n8; k += 8)
        for (unsigned j = 0; j < 8; j++) {
            const float a = std::fabs(in[k + j]);
            const bool use = a > 0.0f && a < INFINITY; // NaN fails both
            part[j] += use ? std::sqrt(a) : 0.0f;
            cnt[j] += use ? 1.0f : 0.0f;
        }
}

const float* info_table()
{
    static const auto table = [] {
        std::array<float, info_bins> t{};
        for (unsigned i = 1; i < info_bins; i++) {
            const double q = 1.0 / (1.0 + std::exp((i + 0.5) / info_step)); // P(wrong sign)
            t[i] = static_cast<float>(1.0 + q * std::log2(q) + (1.0 - q) * std::log2(1.0 - q));
        }
        t[info_bins - 1] = 1.0f;
        return t;
    }();
    return table.data();
}

void info_sums_generic(const float* in, std::size_t n8, float* part, float* cnt)
{
    const float* table = info_table();
    for (std::size_t k = 0; k < n8; k += 8)
        for (unsigned j = 0; j < 8; j++) {
            const float v = in[k + j];
            const float a = v == v ? std::fabs(v) : 0.0f;
            part[j] += table[static_cast<int>(std::min(a * info_step, info_bins - 1.0f))];
            cnt[j] += a > 0.0f ? 1.0f : 0.0f;
        }
}

bool any_received_generic(const float* in, unsigned n)
{
    return std::any_of(in, in + n, [](float v) { return v != 0.0f && v == v; });
}

template <typename T>
unsigned unsatisfied_generic(const T* t, unsigned deg, unsigned zp, unsigned zc)
{
    unsigned bad = 0;
    for (unsigned z = 0; z < zc; z++) {
        T x = 0;
        for (unsigned e = 0; e < deg; e++)
            x ^= t[e * zp + z];
        bad += x < 0 ? 1u : 0u;
    }
    return bad;
}

// Both widths (the AVX2 unit's fallback on other CPUs calls them too).
template bool layer_generic(std::int8_t*, std::int8_t*, unsigned, unsigned, unsigned, std::int8_t);
template bool layer_generic(std::int16_t*, std::int16_t*, unsigned, unsigned, unsigned, std::int16_t);
template void quantize_generic(const float*, unsigned, float, std::int8_t*);
template void quantize_generic(const float*, unsigned, float, std::int16_t*);
template unsigned unsatisfied_generic(const std::int8_t*, unsigned, unsigned, unsigned);
template unsigned unsatisfied_generic(const std::int16_t*, unsigned, unsigned, unsigned);

} // namespace ldpc_detail

using namespace ldpc_detail;

nr_ldpc_decoder::nr_ldpc_decoder(int base_graph, unsigned zc, unsigned max_iterations)
    : d_bg(base_graph), d_zc(zc), d_zp((zc + lanes - 1) / lanes * lanes),
      d_cols(nr_base_graph::get(base_graph).cols),
      d_max_iter(check_at_least("max_iterations", max_iterations, 1u)),
      d_simd(avx2_available())
{
    const auto rows = nr_lifted_rows(base_graph, zc);
    std::vector<unsigned> col_degree(d_cols, 0);
    unsigned max_degree = 0;
    for (unsigned i = 0; i < rows.size(); i++) {
        d_layers.push_back({ i, static_cast<unsigned>(d_edges.size()), static_cast<unsigned>(rows[i].size()) });
        for (const auto& e : rows[i]) {
            d_edges.push_back(e);
            col_degree[e.col]++;
        }
        max_degree = std::max<unsigned>(max_degree, rows[i].size());
    }
    // The degree-one column of a row (its extension parity bit); rows 0 .. 3 have none.
    d_row_parity.assign(rows.size(), d_cols);
    for (unsigned i = 0; i < rows.size(); i++)
        for (const auto& e : rows[i])
            if (col_degree[e.col] == 1)
                d_row_parity[i] = e.col;
    d_l.assign(std::size_t{ d_cols } * d_zp, 0);
    d_received.assign(d_cols, 0);
    d_r.assign(d_edges.size() * d_zp, 0);
    d_t.assign(std::size_t{ max_degree } * d_zp, 0);
}

void nr_ldpc_decoder::set_max_iterations(unsigned max_iterations)
{
    d_max_iter = check_at_least("max_iterations", max_iterations, 1u);
}

void nr_ldpc_decoder::set_simd(bool allow) { d_simd = allow && avx2_available(); }

nr_ldpc_decode_result
nr_ldpc_decoder::decode(const float* llr, std::uint8_t* c, const std::uint8_t* nonzero_columns)
{
    const std::size_t n = this->n();
    // Columns that received nothing (at a high rate most parity columns) are neither summed
    // nor quantised: their fixed-point LLRs are 0.
    for (std::size_t j = 2; j < d_cols; j++) {
        const float* in = llr + (j - 2) * d_zc;
        if (nonzero_columns && !nonzero_columns[j - 2])
            d_received[j] = 0;
        else
            d_received[j] = d_simd ? any_received_avx2(in, d_zc) : any_received_generic(in, d_zc);
    }
    // The scale maps (mean sqrt|L|)^2 over the finite non-zero LLRs to a target. For one
    // Gaussian cluster (BPSK, QPSK) that is about the mean magnitude; for the bit levels of
    // 16- to 256-QAM, whose magnitudes differ by up to 8x, it stays near the weak levels'
    // scale, so their LLRs keep their resolution and the strong ones saturate (they are
    // reliable). 8 partial sums vectorise.
    float part[8] = {}, cnt[8] = {};
    const std::size_t n8 =
        received_sums(llr, d_simd ? root_sums_avx2 : root_sums_generic, part, cnt);
    double sum = 0.0, count = 0.0;
    for (unsigned j = 0; j < 8; j++) {
        sum += part[j];
        count += cnt[j];
    }
    for (std::size_t k = n8; k < n; k++) {
        const float a = std::fabs(llr[k]);
        if (a > 0.0f && a < INFINITY) {
            sum += std::sqrt(a);
            count += 1.0;
        }
    }
    // Headroom: an a-posteriori LLR sums its channel value and up to d_max messages and
    // saturates, so the int8 target shrinks with the largest column degree of the rows
    // decoded (BG1 at rate 0.9: 5 -> 28; 256-QAM at R 0.82: 7 -> 21; QPSK at R 0.3: 17 -> 9.3).
    // Beyond int8_max_degree the int16 path decodes, at 4x the scale: saturated a-posteriori
    // sums were the error floor of the low-rate words (docs/nr_coding.md).
    const unsigned d_max = select_layers();
    const double target = std::clamp(168.0 / (1.0 + d_max), 8.0, 32.0);
    // At least gain / offset_llr steps per LLR unit: beta exact in int8 (1 step), within 1/8
    // in int16. Near their threshold the LLRs of 64- and 256-QAM are 2-4x those of BPSK, and
    // at the target's scale beta 0.5 rounded to 0.69 and 0 LLR in int8 and to 0.63 in
    // 256-QAM's int16 re-decode (rate 0.9: 45 % of 256-QAM's words at its BLER 10 % point
    // lost to fixed point; docs/nr_coding.md).
    const double root_mean = count > 0.0 ? sum / count : 0.0, mean2 = root_mean * root_mean;
    const auto scale_of = [&](double gain) {
        if (mean2 <= 0.0)
            return 1.0f;
        return static_cast<float>(std::max(target * gain / mean2, gain / offset_llr));
    };
    const float wide_scale = scale_of(fixed<std::int16_t>::target_gain);
    if (d_max <= int8_max_degree) {
        const float scale = scale_of(fixed<std::int8_t>::target_gain);
        set_offset(scale);
        const nr_ldpc_decode_result res = quantize_and_run<std::int8_t>(llr, scale, c);
        if (!near_codeword(res) && !above_capacity(llr, res))
            return res;
        set_offset(wide_scale);
        return redecoded(quantize_and_run<std::int16_t>(llr, wide_scale, c));
    }
    set_offset(wide_scale);
    return quantize_and_run<std::int16_t>(llr, wide_scale, c);
}

void nr_ldpc_decoder::set_offset(float scale)
{
    d_offset = static_cast<int>(std::min(std::lround(offset_llr * scale), 127L));
}

bool nr_ldpc_decoder::near_codeword(const nr_ldpc_decode_result& res)
{
    if (res.parity_ok)
        return false;
    // The int8 failures that int16 decodes (saturated sums, the offset's coarse step) end a
    // few checks from a codeword; a word below the code's threshold leaves many.
    const std::size_t checks = d_active.size() * std::size_t{ d_zc };
    std::size_t bad = 0;
    for (const layer& ly : d_active) {
        bad += unsatisfied<std::int8_t>(ly);
        if (bad * near_codeword_fraction > checks)
            return false;
    }
    return true;
}

std::size_t
nr_ldpc_decoder::received_sums(const float* llr, sums_fn fn, float* part, float* cnt) const
{
    // Over runs of received columns widened to multiples of 8 (the skipped values are 0 or
    // NaN and add nothing): lane = index mod 8, the 8 partial sums of all n8 values.
    const std::size_t n8 = n() / 8 * 8;
    std::size_t done = 0;
    for (std::size_t j = 2; j < d_cols;) {
        std::size_t e = j;
        while (e < d_cols && d_received[e])
            e++;
        if (e > j) {
            const std::size_t lo = std::max(done, (j - 2) * d_zc / 8 * 8);
            const std::size_t hi = std::min(n8, ((e - 2) * d_zc + 7) / 8 * 8);
            if (lo < hi) {
                fn(llr + lo, hi - lo, part, cnt);
                done = hi;
            }
        }
        j = e + 1;
    }
    return n8;
}

bool nr_ldpc_decoder::above_capacity(const float* llr, const nr_ldpc_decode_result& res) const
{
    if (res.parity_ok)
        return false;
    // A word fails far from a codeword below the code's threshold, but also, rarely, above
    // it, where int16 decodes it: the mean mutual information of the received LLRs (what the
    // channel carried per bit) against the code rate tells the two apart, whatever the
    // modulation. Fillers (+inf) add 1 to both the information and K.
    float part[8] = {}, cnt[8] = {};
    const std::size_t n8 =
        received_sums(llr, d_simd ? info_sums_avx2 : info_sums_generic, part, cnt);
    float tail[8] = {};
    std::copy(llr + n8, llr + n(), tail);
    info_sums_generic(tail, 8, part, cnt);
    double info = 0.0, count = 0.0;
    for (unsigned j = 0; j < 8; j++) {
        info += part[j];
        count += cnt[j];
    }
    return info - static_cast<double>(k()) >= capacity_margin * count;
}

nr_ldpc_decode_result nr_ldpc_decoder::redecoded(nr_ldpc_decode_result res)
{
    res.redecoded = true;
    return res;
}

template <typename T>
nr_ldpc_decode_result nr_ldpc_decoder::quantize_and_run(const float* llr, float scale, std::uint8_t* c)
{
    T* l = reinterpret_cast<T*>(d_l.data());
    std::fill(l, l + 2 * d_zp, 0);
    for (std::size_t j = 2; j < d_cols; j++) {
        const float* in = llr + (j - 2) * d_zc;
        T* out = l + j * d_zp;
        if (!d_received[j])
            std::fill(out, out + d_zc, 0);
        else if (d_simd)
            quantize_avx2(in, d_zc, scale, out);
        else
            quantize_generic(in, d_zc, scale, out);
    }
    return run<T>(c);
}

nr_ldpc_decode_result nr_ldpc_decoder::decode_int8(const std::int8_t* llr, std::uint8_t* c, std::int8_t offset)
{
    d_offset = std::max<int>(offset, 0);
    for (std::size_t j = 2; j < d_cols; j++) {
        const std::int8_t* in = llr + (j - 2) * d_zc;
        d_received[j] = std::any_of(in, in + d_zc, [](std::int8_t v) { return v != 0; });
    }
    if (select_layers() > int8_max_degree)
        return widen_and_run<std::int16_t>(llr, c);
    const nr_ldpc_decode_result res = widen_and_run<std::int8_t>(llr, c);
    return near_codeword(res) ? redecoded(widen_and_run<std::int16_t>(llr, c)) : res;
}

template <typename T>
nr_ldpc_decode_result nr_ldpc_decoder::widen_and_run(const std::int8_t* llr, std::uint8_t* c)
{
    T* l = reinterpret_cast<T*>(d_l.data());
    std::fill(l, l + std::size_t{ d_cols } * d_zp, 0);
    for (std::size_t j = 2; j < d_cols; j++) {
        const std::int8_t* in = llr + (j - 2) * d_zc;
        T* out = l + j * d_zp;
        for (unsigned z = 0; z < d_zc; z++)
            out[z] = std::max<std::int8_t>(in[z], -127);
    }
    return run<T>(c);
}

unsigned nr_ldpc_decoder::select_layers()
{
    // Rows whose own parity column received nothing carry no information: skip them.
    d_active.clear();
    std::vector<unsigned> degree(d_cols, 0);
    unsigned d_max = 0;
    for (const layer& ly : d_layers) {
        const unsigned pc = d_row_parity[ly.row];
        if (pc < d_cols && !d_received[pc])
            continue;
        d_active.push_back(ly);
        for (unsigned k = 0; k < ly.degree; k++)
            d_max = std::max(d_max, ++degree[d_edges[ly.first_edge + k].col]);
    }
    return d_max;
}

template <typename T>
void nr_ldpc_decoder::gather(const layer& ly)
{
    // t[z] = L[(z + s) mod zc] for each column of the row
    const T* l = reinterpret_cast<const T*>(d_l.data());
    T* t = reinterpret_cast<T*>(d_t.data());
    for (unsigned k = 0; k < ly.degree; k++) {
        const nr_lifted_edge& e = d_edges[ly.first_edge + k];
        const T* col = l + std::size_t{ e.col } * d_zp;
        T* tk = t + std::size_t{ k } * d_zp;
        std::memcpy(tk, col + e.shift, (d_zc - e.shift) * sizeof(T));
        std::memcpy(tk + d_zc - e.shift, col, e.shift * sizeof(T));
    }
}

template <typename T>
unsigned nr_ldpc_decoder::unsatisfied(const layer& ly)
{
    gather<T>(ly);
    const T* t = reinterpret_cast<const T*>(d_t.data());
    return d_simd ? unsatisfied_avx2(t, ly.degree, d_zp, d_zc)
                  : unsatisfied_generic(t, ly.degree, d_zp, d_zc);
}

template <typename T>
nr_ldpc_decode_result nr_ldpc_decoder::run(std::uint8_t* c)
{
    const unsigned zc = d_zc, zp = d_zp;
    nr_ldpc_decode_result res;
    T* t = reinterpret_cast<T*>(d_t.data());
    T* l = reinterpret_cast<T*>(d_l.data());
    const auto offset = static_cast<T>(std::min(d_offset, fixed<T>::max));
    T* r0 = reinterpret_cast<T*>(d_r.data());
    for (const layer& ly : d_active)
        std::fill(r0 + std::size_t{ ly.first_edge } * zp, r0 + std::size_t{ ly.first_edge + ly.degree } * zp, 0);
    for (unsigned it = 1; it <= d_max_iter; it++) {
        d_failed.clear();
        for (const layer& ly : d_active) {
            gather<T>(ly);
            T* r = r0 + std::size_t{ ly.first_edge } * zp;
            const bool ok = d_simd ? layer_avx2(t, r, ly.degree, zp, zc, offset)
                                   : layer_generic(t, r, ly.degree, zp, zc, offset);
            if (!ok)
                d_failed.push_back(&ly);
            for (unsigned k = 0; k < ly.degree; k++) { // scatter back
                const nr_lifted_edge& e = d_edges[ly.first_edge + k];
                T* col = l + std::size_t{ e.col } * zp;
                std::memcpy(col + e.shift, t + k * zp, (zc - e.shift) * sizeof(T));
                std::memcpy(col, t + k * zp + zc - e.shift, e.shift * sizeof(T));
            }
        }
        res.iterations = it;
        // Rows that failed at their visit (e.g. before the punctured columns got values)
        // are checked again; when they hold, a full syndrome on the final hard decisions
        // confirms (a row that held at its visit may have changed since).
        const auto holds = [this](const layer& ly) { return unsatisfied<T>(ly) == 0; };
        const bool failed_now_hold = std::all_of(d_failed.begin(), d_failed.end(),
                                                 [&](const layer* ly) { return holds(*ly); });
        if (failed_now_hold && std::all_of(d_active.begin(), d_active.end(), holds)) {
            res.parity_ok = true;
            break;
        }
    }
    const unsigned info = nr_base_graph::get(d_bg).info_cols;
    for (unsigned j = 0; j < info; j++) {
        const T* col = l + std::size_t{ j } * zp;
        for (unsigned z = 0; z < zc; z++)
            c[std::size_t{ j } * zc + z] = col[z] < 0 ? 1 : 0;
    }
    return res;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
