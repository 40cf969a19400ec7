/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Resource elements per second of kernel::scene_echo (paper numerology, 3 targets)
// with and without noise, and of the noise generator against std::normal_distribution.
// Run outside ctest (ctest sets VOLK_GENERIC=1).

#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

std::vector<gr_complex> qpsk(unsigned n)
{
    std::mt19937 gen(1);
    std::vector<gr_complex> s(n);
    const float a = 0.70710678f;
    for (auto& v : s)
        v = gr_complex(gen() & 1 ? a : -a, gen() & 1 ? a : -a);
    return s;
}

void run_echo(benchmark::State& state, bool noise, bool want_h)
{
    const auto num = numerology::preset("paper");
    kernel::scene_echo k(num, geometry::preset("paper"), scene::preset("paper3"));
    kernel::gaussian_noise g(5);
    const unsigned n = num.num_subcarriers;
    const auto s = qpsk(n);
    std::vector<gr_complex> y(n), h(n);
    std::uint64_t m = 0;
    for (auto _ : state) {
        k.echo(m, s.data(), y.data(), want_h ? h.data() : nullptr, noise ? &g : nullptr, 0.1f);
        benchmark::DoNotOptimize(y.data());
        m = (m + 1) % 48000;
    }
    state.SetItemsProcessed(state.iterations() * n);
}

// As in a flowgraph: input and output cycle through 512-symbol (13.6 MB) buffers,
// the size GNU Radio allocates for items of 3333 complex, so they stream from memory.
void BM_EchoWithNoiseStreaming(benchmark::State& state)
{
    const auto num = numerology::preset("paper");
    kernel::scene_echo k(num, geometry::preset("paper"), scene::preset("paper3"));
    kernel::gaussian_noise g(5);
    const unsigned n = num.num_subcarriers;
    const unsigned ring = 512;
    std::vector<gr_complex> s(static_cast<size_t>(ring) * n), y(s.size());
    const auto sym = qpsk(n);
    for (unsigned r = 0; r < ring; r++)
        std::copy(sym.begin(), sym.end(), s.begin() + static_cast<size_t>(r) * n);
    std::uint64_t m = 0;
    const bool noise = state.range(0) != 0;
    for (auto _ : state) {
        const size_t off = static_cast<size_t>(m % ring) * n;
        k.echo(m, s.data() + off, y.data() + off, nullptr, noise ? &g : nullptr, 0.1f);
        benchmark::DoNotOptimize(y.data());
        m++;
    }
    state.SetItemsProcessed(state.iterations() * n);
}

void BM_EchoNoiseFree(benchmark::State& state) { run_echo(state, false, false); }
void BM_EchoNoiseFreeWithReference(benchmark::State& state) { run_echo(state, false, true); }
void BM_EchoWithNoise(benchmark::State& state) { run_echo(state, true, false); }
void BM_EchoWithNoiseAndReference(benchmark::State& state) { run_echo(state, true, true); }

void BM_NoiseOurs(benchmark::State& state)
{
    kernel::gaussian_noise g(5, state.range(0) != 0);
    std::vector<gr_complex> z(3333);
    std::uint64_t b = 0;
    for (auto _ : state) {
        g.generate(b++, 1.0f, z.data(), z.size());
        benchmark::DoNotOptimize(z.data());
    }
    state.SetItemsProcessed(state.iterations() * z.size());
    state.SetLabel(g.implementation());
}

// The peer: the standard library's normal distribution (two per complex sample).
void BM_NoiseStdNormal(benchmark::State& state)
{
    std::mt19937_64 gen(5);
    std::normal_distribution<float> normal(0.0f, 0.70710678f);
    std::vector<gr_complex> z(3333);
    for (auto _ : state) {
        for (auto& v : z) {
            const float re = normal(gen);
            v = gr_complex(re, normal(gen));
        }
        benchmark::DoNotOptimize(z.data());
    }
    state.SetItemsProcessed(state.iterations() * z.size());
}

} // namespace

BENCHMARK(BM_EchoNoiseFree);
BENCHMARK(BM_EchoNoiseFreeWithReference);
BENCHMARK(BM_EchoWithNoise);
BENCHMARK(BM_EchoWithNoiseAndReference);
BENCHMARK(BM_EchoWithNoiseStreaming)->Arg(0)->Arg(1);
BENCHMARK(BM_NoiseOurs)->Arg(1)->Arg(0);
BENCHMARK(BM_NoiseStdNormal);
