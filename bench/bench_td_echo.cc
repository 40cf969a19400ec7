/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Samples per second of kernel::td_echo at the paper numerology (122.88 Msps) with the
// paper3 scene, against the FIR length, with and without noise, and of the bare
// multipath_fir for one path (the cost per tap). Run outside ctest (ctest sets
// VOLK_GENERIC=1).

#include <gnuradio/nrsar/kernel/td_echo.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

std::vector<gr_complex> samples(std::size_t n)
{
    std::mt19937 gen(1);
    std::normal_distribution<float> g(0.0f, 0.7f);
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(gen), g(gen));
    return x;
}

// One work() call's worth (8192 samples) at a time, the platform moving on.
void BM_TdEchoPaper3(benchmark::State& state)
{
    const auto num = numerology::preset("paper");
    const unsigned taps = static_cast<unsigned>(state.range(0));
    const bool noise = state.range(1) != 0;
    kernel::td_echo k(num, geometry::preset("paper"), scene::preset("paper3"), taps);
    k.fir().set_simd(state.range(2) != 0);
    k.fir().set_avx512(state.range(2) == 2);
    state.SetLabel(k.fir().implementation());
    kernel::gaussian_noise g(5);
    const std::size_t n = 8192, hist = k.history();
    const auto x = samples(hist + n);
    std::vector<gr_complex> y(n);
    std::uint64_t s0 = 0;
    for (auto _ : state) {
        k.process(s0, x.data() + hist, y.data(), n, noise ? &g : nullptr, 0.1f);
        benchmark::DoNotOptimize(y.data());
        s0 += n;
    }
    state.SetItemsProcessed(state.iterations() * n);
    state.counters["span"] = k.fir().lag_hi() - k.fir().lag_lo() + 1;
}

void BM_MultipathFirOnePath(benchmark::State& state)
{
    const unsigned taps = static_cast<unsigned>(state.range(0));
    kernel::multipath_fir fir(taps, 9.0, 2000);
    fir.set_simd(state.range(1) != 0);
    fir.set_avx512(state.range(1) == 2);
    state.SetLabel(fir.implementation());
    const kernel::echo_path p{ 900.37, 1.0 };
    fir.set_paths(&p, 1);
    const std::size_t n = 8192;
    const auto x = samples(2000 + n);
    std::vector<gr_complex> y(n);
    for (auto _ : state) {
        fir.filter(x.data() + 2000, y.data(), n);
        benchmark::DoNotOptimize(y.data());
    }
    state.SetItemsProcessed(state.iterations() * n);
}

// Per-symbol set-up: eq. (8) delays and the FIR taps (double) for the paper3 scene.
void BM_TdEchoSymbolSetup(benchmark::State& state)
{
    const auto num = numerology::preset("paper");
    kernel::td_echo k(num, geometry::preset("paper"), scene::preset("paper3"), 32);
    std::uint64_t m = 0;
    for (auto _ : state) {
        const auto p = k.paths(m++);
        benchmark::DoNotOptimize(k.fir().set_paths(p.data(), p.size()));
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace

// Args: taps, noise (0/1), loop: one VOLK dot product per output (0), AVX2 (1), AVX-512
// where the CPU has it (2; the label names the loop that ran).
BENCHMARK(BM_TdEchoPaper3)->ArgsProduct({ { 16, 32, 64 }, { 0, 1 }, { 0, 1, 2 } });
BENCHMARK(BM_TdEchoSymbolSetup);
BENCHMARK(BM_MultipathFirOnePath)->ArgsProduct({ { 16, 32, 64 }, { 0, 1, 2 } });
