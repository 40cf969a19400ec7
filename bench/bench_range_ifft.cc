/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of range compression (items = OFDM symbols) at N = 3333 for the FFT sizes
// of SPEC 5: no padding (3333), 7-smooth padding (fast_fft_size = 3360), power of two (4096).

#include <gnuradio/nrsar/kernel/range_ifft.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

void BM_range_ifft(benchmark::State& state)
{
    const unsigned n = state.range(0);
    const unsigned nfft = state.range(1);
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    kernel::range_ifft k(n, nfft, gr::fft::window::WIN_HAMMING);
    std::vector<gr_complex> out(k.num_bins());
    for (auto _ : state) {
        k.execute(x.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace

BENCHMARK(BM_range_ifft)
    ->Args({ 3333, 3333 })
    ->Args({ 3333, 3360 })
    ->Args({ 3333, 4096 });

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
