/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// NR LDPC decoder (TS 38.212 5.3.2) on one code block: BG1, Zc = 384, K = 8448 information
// bits, rate 0.9 (the first 9386 bits of d sent, BPSK over AWGN), at most 8 iterations.
// Items = decoded information bits (K per block): items_per_second is the information
// throughput of one core. Words: 64 blocks drawn once at a fixed seed per SNR.
//   Es/N0 = 5 dB: about 2 dB above the BI-AWGN limit of rate 0.9, early termination
//                 after a few iterations;
//   Es/N0 = 0 dB: far below it, never converges: all 8 iterations (the worst case).
//   Es/N0 = 3.5 / 3.6 / 3.7 dB: the waterfall, BLER about 40 % / 10 % / 1 % (512 words):
//                 the words whose int8 decode fails near a codeword are decoded again in
//                 int16, 40 % of them at 3.5 dB (the most over the SNR sweep).
// 64- and 256-QAM at rate 0.9 (rate matching with the Qm bit interleaver, complex AWGN, the
// module's max-log demapper; 512 words): Es/N0 18.9 / 24.4 dB, BLER about 3 % / 13 %, where
// the int8 decode's loss and the int16 re-decode were largest. A short code at its BLER
// 10 % point: BG2 Zc 40, K' 308 (92 fillers), 64-QAM at Es/N0 20 dB (E 342 bits, 512 words).
// The same with the scalar path, and the encoder. Low rate (the int16 path of the decoder):
// BG2, Zc = 208 (K = 2080), rate 0.3 (the code block of qam64 MCS 4), at most 8
// iterations, at Es/N0 = -4 dB (QPSK SNR -1 dB, BLER about 1 % with 8 iterations) and
// -10 dB (never converges).

#include "../tests/nr_qam_words.h"
#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc_decoder.h>
#include <cmath>
#include <random>
#include <vector>

using namespace gr::nrsar::kernel;

namespace {

constexpr unsigned zc = 384;
constexpr unsigned n_words = 64; // per SNR, unless given

struct words {
    std::vector<std::vector<float>> llr;
    std::vector<std::vector<std::uint8_t>> info;
};

words make_words(double esn0_db, double rate, int bg, unsigned lift, unsigned count)
{
    nr_ldpc_encoder enc(bg, lift);
    const std::size_t K = enc.k(), n_tx = static_cast<std::size_t>(K / rate);
    const double sigma = std::sqrt(0.5 / std::pow(10.0, esn0_db / 10.0));
    std::mt19937 rng(12);
    std::normal_distribution<double> noise(0.0, sigma);
    words w;
    std::vector<std::uint8_t> d(enc.n());
    for (unsigned b = 0; b < count; b++) {
        std::vector<std::uint8_t> c(K);
        for (auto& v : c)
            v = rng() & 1u;
        enc.encode(c.data(), d.data());
        std::vector<float> llr(enc.n(), 0.0f);
        for (std::size_t k = 0; k < n_tx; k++)
            llr[k] = static_cast<float>(2.0 * ((d[k] ? -1.0 : 1.0) + noise(rng)) / (sigma * sigma));
        w.llr.push_back(std::move(llr));
        w.info.push_back(std::move(c));
    }
    return w;
}

words make_qam_words(gr::nrsar::modulation mod,
                     double esn0_db,
                     unsigned count,
                     int bg = 1,
                     unsigned lift = zc,
                     unsigned k_prime = 0)
{
    nrsar_test::nr_qam_words source(mod, esn0_db, 12, bg, lift, k_prime);
    words w;
    for (unsigned b = 0; b < count; b++) {
        std::vector<std::uint8_t> c;
        std::vector<float> llr;
        source.draw(c, llr);
        w.llr.push_back(std::move(llr));
        w.info.push_back(std::move(c));
    }
    return w;
}

void decode_words(benchmark::State& state, const words& w, bool simd, int bg, unsigned lift)
{
    const unsigned count = static_cast<unsigned>(w.llr.size());
    nr_ldpc_decoder dec(bg, lift, 8);
    dec.set_simd(simd);
    std::vector<std::uint8_t> out(dec.k());
    std::size_t blocks = 0, iterations = 0, ok = 0, redecoded = 0;
    for (auto _ : state) {
        const unsigned b = blocks % count;
        const auto r = dec.decode(w.llr[b].data(), out.data());
        iterations += r.iterations;
        redecoded += r.redecoded ? 1 : 0;
        ok += out == w.info[b] ? 1 : 0;
        blocks++;
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(blocks * dec.k()));
    state.counters["iterations"] = double(iterations) / double(blocks);
    state.counters["bler"] = 1.0 - double(ok) / double(blocks);
    state.counters["redecoded"] = double(redecoded) / double(blocks);
    state.counters["Mbit/s"] = benchmark::Counter(double(blocks * dec.k()) / 1e6, benchmark::Counter::kIsRate);
    state.SetLabel(dec.simd() ? "avx2" : "scalar");
}

void decode(benchmark::State& state, double esn0_db, bool simd, double rate = 0.9, int bg = 1,
            unsigned lift = zc, unsigned count = n_words)
{
    decode_words(state, make_words(esn0_db, rate, bg, lift, count), simd, bg, lift);
}

void BM_nr_ldpc_decode_5dB(benchmark::State& s) { decode(s, 5.0, true); }
void BM_nr_ldpc_decode_0dB_8it(benchmark::State& s) { decode(s, 0.0, true); }
void BM_nr_ldpc_decode_3p5dB(benchmark::State& s) { decode(s, 3.5, true, 0.9, 1, zc, 512); }
void BM_nr_ldpc_decode_3p6dB(benchmark::State& s) { decode(s, 3.6, true, 0.9, 1, zc, 512); }
void BM_nr_ldpc_decode_3p7dB(benchmark::State& s) { decode(s, 3.7, true, 0.9, 1, zc, 512); }
void BM_nr_ldpc_decode_qam64_18p9dB(benchmark::State& s)
{
    decode_words(s, make_qam_words(gr::nrsar::modulation::QAM64, 18.9, 512), true, 1, zc);
}
void BM_nr_ldpc_decode_qam256_24p4dB(benchmark::State& s)
{
    decode_words(s, make_qam_words(gr::nrsar::modulation::QAM256, 24.4, 512), true, 1, zc);
}
void BM_nr_ldpc_decode_bg2_k308_qam64_20dB(benchmark::State& s)
{
    const auto w = make_qam_words(gr::nrsar::modulation::QAM64, 20.0, 512, 2, 40, 308);
    decode_words(s, w, true, 2, 40);
}
void BM_nr_ldpc_decode_5dB_scalar(benchmark::State& s) { decode(s, 5.0, false); }
void BM_nr_ldpc_decode_0dB_8it_scalar(benchmark::State& s) { decode(s, 0.0, false); }
void BM_nr_ldpc_decode_bg2_r03_m4dB(benchmark::State& s) { decode(s, -4.0, true, 0.3, 2, 208); }
void BM_nr_ldpc_decode_bg2_r03_m10dB_8it(benchmark::State& s) { decode(s, -10.0, true, 0.3, 2, 208); }

void BM_nr_ldpc_encode(benchmark::State& state)
{
    nr_ldpc_encoder enc(1, zc);
    std::vector<std::uint8_t> c(enc.k()), d(enc.n());
    std::mt19937 rng(1);
    for (auto& v : c)
        v = rng() & 1u;
    for (auto _ : state) {
        enc.encode(c.data(), d.data());
        benchmark::DoNotOptimize(d.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * enc.k()));
}

} // namespace

BENCHMARK(BM_nr_ldpc_decode_5dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_0dB_8it)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_3p5dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_3p6dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_3p7dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_qam64_18p9dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_qam256_24p4dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_bg2_k308_qam64_20dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_5dB_scalar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_0dB_8it_scalar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_bg2_r03_m4dB)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_decode_bg2_r03_m10dB_8it)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_nr_ldpc_encode)->Unit(benchmark::kMicrosecond);
