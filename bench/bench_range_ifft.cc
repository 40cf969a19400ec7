/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of range compression (items = OFDM symbols) at N = 3333 for the FFT sizes
// of SPEC 5: no padding (3333), 7-smooth padding (fast_fft_size = 3360), power of two (4096),
// hot (one symbol) and cycling over a flowgraph edge's worth, against fft_vcc's per-item work.

#include <gnuradio/nrsar/kernel/range_ifft.h>
#include <benchmark/benchmark.h>
#include <gnuradio/fft/fft.h>
#include <volk/volk.h>
#include <cstring>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

// The block's input in a flowgraph: GNU Radio gives a 3333-complex edge 512 items
// (lcm(26664, 4096) bytes = 13.6 MB), which the upstream block keeps nearly full, so each
// symbol arrives from beyond the core's L2. ring = how many symbols the input cycles over.
std::vector<gr_complex> symbol_ring(unsigned len, unsigned ring)
{
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(std::size_t(len) * ring);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

// args: N, FFT size, ring
void BM_range_ifft(benchmark::State& state)
{
    const unsigned n = state.range(0);
    const unsigned nfft = state.range(1);
    const unsigned ring = state.range(2);
    const auto x = symbol_ring(n, ring);
    kernel::range_ifft k(n, nfft, gr::fft::window::WIN_HAMMING);
    std::vector<gr_complex> out(k.num_bins());
    unsigned i = 0;
    for (auto _ : state) {
        k.execute(x.data() + std::size_t(i) * n, out.data());
        benchmark::DoNotOptimize(out.data());
        i = i + 1 == ring ? 0 : i + 1;
    }
    state.SetItemsProcessed(state.iterations());
}

// The peer of nrsar-bench's range_ifft rows: fft_vcc's work() per item (window multiply
// over the padded length into FFTW's input, transform, copy of every bin), fed pre-padded
// 3360-complex symbols, whose edge GNU Radio sizes at 16 items (430 kB). arg: ring
void BM_fft_vcc(benchmark::State& state)
{
    const unsigned n = 3333, nfft = 3360, ring = state.range(0);
    const auto x = symbol_ring(nfft, ring);
    gr::fft::fft_complex_rev f(nfft, 1);
    std::vector<float> w = gr::fft::window::build(gr::fft::window::WIN_HAMMING, n, 0.0, false);
    w.resize(nfft, 0.0f);
    std::vector<gr_complex> out(nfft);
    unsigned i = 0;
    for (auto _ : state) {
        const gr_complex* in = x.data() + std::size_t(i) * nfft;
        volk_32fc_32f_multiply_32fc(f.get_inbuf(), in, w.data(), nfft);
        f.execute();
        std::memcpy(out.data(), f.get_outbuf(), sizeof(gr_complex) * nfft);
        benchmark::DoNotOptimize(out.data());
        i = i + 1 == ring ? 0 : i + 1;
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace

BENCHMARK(BM_range_ifft)
    ->Args({ 3333, 3333, 1 })
    ->Args({ 3333, 3360, 1 })
    ->Args({ 3333, 4096, 1 })
    ->Args({ 3333, 3360, 16 })
    ->Args({ 3333, 3360, 512 });
BENCHMARK(BM_fft_vcc)->Arg(1)->Arg(16)->Arg(512);

#include <gnuradio/nrsar/kernel/finite_guard.h>

namespace {
// The non-finite check every block runs on its input before the transform.
void BM_finite_guard(benchmark::State& state)
{
    const std::size_t n = state.range(0);
    std::vector<gr_complex> x(n, gr_complex(0.5f, -0.25f));
    kernel::finite_guard guard;
    for (auto _ : state) {
        std::size_t bad = 0;
        benchmark::DoNotOptimize(guard.guard(x.data(), n, bad));
    }
    state.SetItemsProcessed(state.iterations());
}
} // namespace

BENCHMARK(BM_finite_guard)->Arg(3333);

