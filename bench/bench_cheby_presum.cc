/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of the azimuth presummer (items = input pulses of K = 256 range bins) for
// each method at D = 10 and for CHEBY at D = 4, 12, 40.

#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

void BM_cheby_presum(benchmark::State& state)
{
    const unsigned k = 256;
    kernel::presum_config cfg;
    cfg.method = static_cast<presum_method>(state.range(0));
    cfg.decim = state.range(1);
    kernel::cheby_presum ps(numerology::preset("paper"),
                            geometry::preset("paper"),
                            scene::preset("paper3"),
                            k,
                            1000.0,
                            1.5,
                            cfg);
    const unsigned pulses = 240;
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(std::size_t(pulses) * k), out(k);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    for (auto _ : state) {
        for (unsigned p = 0; p < pulses; ++p)
            ps.push(x.data() + std::size_t(p) * k, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * pulses);
}

} // namespace

BENCHMARK(BM_cheby_presum)
    ->ArgNames({ "method", "D" })
    ->Args({ 0, 10 })
    ->Args({ 1, 10 })
    ->Args({ 2, 10 })
    ->Args({ 3, 10 })
    ->Args({ 4, 10 }) // LMS: 2 K L multiply-adds on every input pulse
    ->Args({ 0, 4 })
    ->Args({ 0, 12 })
    ->Args({ 0, 40 });

BENCHMARK_MAIN();
