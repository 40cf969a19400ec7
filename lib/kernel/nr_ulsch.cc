/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_rate_match.h>
#include <gnuradio/nrsar/kernel/nr_ulsch.h>
#include <algorithm>
#include <cstring>
#include <memory>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// out = in with the sign flipped where c = 1 (38.211 6.3.1.1 undone on LLRs). A NaN is an
// erasure (0); +-inf is a known bit, saturated so that HARQ's sums of opposite certainties
// stay finite. The sign flip on the bits.
constexpr float llr_saturation = 1e30f;

void descramble(const float* __restrict in, const std::uint8_t* __restrict c, std::size_t n, float* __restrict out)
{
    std::size_t k = 0;
#ifdef __SSE2__
    // GCC keeps the scalar loop's NaN test as a branch (a tenth of the demo's receiver):
    // 4 at a time, the same results (maxps/minps equal std::max/min for non-NaN values;
    // a NaN is masked to 0 by the ordered compare)
    const __m128 hi = _mm_set1_ps(llr_saturation), lo = _mm_set1_ps(-llr_saturation);
    const __m128i zero = _mm_setzero_si128();
    for (; k + 4 <= n; k += 4) {
        std::int32_t c4;
        std::memcpy(&c4, c + k, 4);
        const __m128i bytes = _mm_cvtsi32_si128(c4);
        const __m128i sign =
            _mm_slli_epi32(_mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero), 31);
        const __m128 v = _mm_xor_ps(_mm_loadu_ps(in + k), _mm_castsi128_ps(sign));
        const __m128 clamped = _mm_min_ps(_mm_max_ps(v, lo), hi);
        _mm_storeu_ps(out + k, _mm_and_ps(clamped, _mm_cmpord_ps(v, v)));
    }
#endif
    for (; k < n; k++) {
        std::uint32_t u;
        std::memcpy(&u, in + k, 4);
        u ^= std::uint32_t{ c[k] } << 31;
        float v;
        std::memcpy(&v, &u, 4);
        out[k] = v != v ? 0.0f : std::min(std::max(v, -llr_saturation), llr_saturation);
    }
}

nr_segmentation segmentation_of(std::size_t tbs, double code_rate)
{
    check_at_least<std::size_t>("tbs", tbs, 24);
    return nr_segmentation::compute(tbs + nr_tb_crc_length(tbs), nr_select_base_graph(tbs, code_rate));
}
} // namespace

nr_ulsch::nr_ulsch(std::size_t tbs,
                   double code_rate,
                   unsigned qm,
                   std::size_t g,
                   unsigned n_layers,
                   std::size_t n_ref,
                   unsigned max_iterations)
    : d_A(tbs),
      d_G(g),
      d_qm(qm),
      d_n_ref(n_ref),
      d_tb_crc(nr_tb_crc_length(tbs) == 24 ? nr_crc_type::crc24a : nr_crc_type::crc16),
      d_seg(segmentation_of(tbs, code_rate)),
      d_E(nr_code_block_e(g, d_seg.C, qm, n_layers)),
      d_enc(d_seg.base_graph, d_seg.Zc),
      d_max_iterations(max_iterations)
{
    d_dec.emplace_back(d_seg.base_graph, d_seg.Zc, max_iterations);
    nr_rate_match_params p;
    p.base_graph = d_seg.base_graph;
    p.zc = d_seg.Zc;
    p.k_prime = d_seg.K_prime;
    p.n_ref = n_ref;
    p.qm = qm;
    p.validate();
    d_tb.resize(d_seg.B);
    d_cb.resize(std::size_t{ d_seg.C } * d_seg.K);
    d_d.resize(d_enc.n());
    d_c.resize(d_seg.K);
    d_soft.assign(std::size_t{ d_seg.C } * d_enc.n(), 0.0f);
    d_soft_columns.assign(std::size_t{ d_seg.C } * (d_enc.n() / d_seg.Zc), 0);
    d_llr.emplace_back(*std::max_element(d_E.begin(), d_E.end()));
    d_e_begin.assign(d_seg.C, 0);
    for (unsigned r = 1; r < d_seg.C; r++)
        d_e_begin[r] = d_e_begin[r - 1] + d_E[r - 1];
    d_cb_iterations.assign(d_seg.C, 0);
    d_cb_parity.assign(d_seg.C, 0);
    d_scr.resize(d_G);
}

void nr_ulsch::scrambling(std::uint32_t c_init)
{
    // 38.211's c_init is the same for every slot of a UE: the sequence is made once
    if (d_scr_valid && c_init == d_scr_c_init)
        return;
    gold_sequence c(c_init);
    c.generate_unpacked(d_scr.data(), d_G);
    d_scr_c_init = c_init;
    d_scr_valid = true;
}

void nr_ulsch::encode(const std::uint8_t* a, unsigned rv, std::uint32_t c_init, std::uint8_t* out)
{
    d_tb_crc.attach(a, d_A, d_tb.data());
    nr_segment(d_tb.data(), d_seg, d_cb.data());
    nr_rate_match_params p;
    p.base_graph = d_seg.base_graph;
    p.zc = d_seg.Zc;
    p.k_prime = d_seg.K_prime;
    p.n_ref = d_n_ref;
    p.rv = rv;
    p.qm = d_qm;
    std::size_t pos = 0;
    for (unsigned r = 0; r < d_seg.C; r++) {
        d_enc.encode(d_cb.data() + std::size_t{ r } * d_seg.K, d_d.data());
        nr_rate_match(d_d.data(), p, d_E[r], out + pos);
        pos += d_E[r];
    }
    scrambling(c_init);
    for (std::size_t i = 0; i < d_G; i++)
        out[i] ^= d_scr[i];
}

void nr_ulsch::set_threads(unsigned threads)
{
    check_range("threads", threads, 1u, 2u);
    while (d_dec.size() < threads) {
        d_dec.emplace_back(d_seg.base_graph, d_seg.Zc, d_max_iterations);
        d_llr.emplace_back(d_llr[0].size());
    }
    d_threads = threads;
    if (threads == 1)
        d_worker.stop();
}

nr_ulsch_result
nr_ulsch::decode(const float* llr, unsigned rv, std::uint32_t c_init, bool combine, std::uint8_t* a)
{
    nr_rate_match_params p;
    p.base_graph = d_seg.base_graph;
    p.zc = d_seg.Zc;
    p.k_prime = d_seg.K_prime;
    p.n_ref = d_n_ref;
    p.rv = rv;
    p.qm = d_qm;
    scrambling(c_init);
    nr_ulsch_result res;
    res.code_blocks = d_seg.C;
    const std::size_t N = d_enc.n();
    // code blocks [begin, end) with the decoder and scratch of thread `part`
    const split_worker::job blocks = [&](std::size_t begin, std::size_t end, unsigned part) {
        float* e_llr = d_llr[part].data();
        for (std::size_t r = begin; r < end; r++) {
            const std::size_t pos = d_e_begin[r];
            descramble(llr + pos, d_scr.data() + pos, d_E[r], e_llr);
            float* soft = d_soft.data() + r * N;
            std::uint8_t* columns = d_soft_columns.data() + r * (N / d_seg.Zc);
            nr_rate_recover(e_llr, p, d_E[r], soft, combine, columns); // !combine: a new TB
            const auto dr = d_dec[part].decode(soft, d_cb.data() + r * d_seg.K, columns);
            d_cb_iterations[r] = dr.iterations;
            d_cb_parity[r] = dr.parity_ok ? 1 : 0;
        }
    };
    if (d_threads == 2 && d_seg.C >= 2)
        d_worker.run(d_seg.C, blocks);
    else
        blocks(0, d_seg.C, 0);
    unsigned iterations = 0;
    res.parity_ok = true;
    for (unsigned r = 0; r < d_seg.C; r++) {
        iterations += d_cb_iterations[r];
        res.parity_ok = res.parity_ok && d_cb_parity[r];
    }
    const auto ok = std::make_unique<bool[]>(d_seg.C);
    nr_desegment(d_cb.data(), d_seg, d_tb.data(), ok.get());
    res.tb_crc_ok = d_tb_crc.check(d_tb.data(), d_seg.B);
    for (unsigned r = 0; r < d_seg.C; r++)
        res.cb_crc_ok += (d_seg.C > 1 ? ok[r] : res.tb_crc_ok) ? 1u : 0u;
    res.mean_iterations = double(iterations) / d_seg.C;
    std::copy(d_tb.begin(), d_tb.begin() + d_A, a);
    return res;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
