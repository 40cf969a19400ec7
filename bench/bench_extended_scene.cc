/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Resource elements per second of kernel::extended_scene for a 256 x 256 map at the paper
// numerology (taps x oversampling), against kernel::scene_echo summing the same scatterers
// exactly. Run outside ctest.

#include <gnuradio/nrsar/kernel/extended_scene.h>
#include <gnuradio/nrsar/kernel/scene_echo.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

kernel::reflectivity_map map256(unsigned n)
{
    kernel::reflectivity_map map;
    map.nx = map.ny = n;
    map.dx = map.dy = 0.5;
    map.x0 = 300.0 - n * 0.25;
    map.y0 = 50.0 - n * 0.25;
    map.values.assign(std::size_t(n) * n, gr_complex(1.0f, 0.0f));
    map.speckle = true;
    map.speckle_seed = 3;
    return map;
}

void BM_ExtendedScene(benchmark::State& state)
{
    const auto num = numerology::preset("paper");
    kernel::extended_scene k(num,
                             geometry::preset("paper"),
                             scene(),
                             { map256(256) },
                             kernel::antenna_beam(),
                             static_cast<unsigned>(state.range(0)),
                             state.range(1) / 100.0);
    std::vector<gr_complex> h(num.num_subcarriers);
    std::uint64_t m = 0;
    for (auto _ : state) {
        k.reference(m, h.data());
        benchmark::DoNotOptimize(h.data());
        m = (m + 1) % 48000;
    }
    state.SetItemsProcessed(state.iterations() * num.num_subcarriers);
}
BENCHMARK(BM_ExtendedScene)
    ->Args({ 4, 200 })
    ->Args({ 6, 200 })
    ->Args({ 8, 200 })
    ->Args({ 12, 200 })
    ->Args({ 6, 125 })
    ->Args({ 8, 150 })
    ->Unit(benchmark::kMillisecond);

// The exact sum by scene_echo (AVX2, K x N) over the same 65536 scatterers.
void BM_SceneEchoSameScatterers(benchmark::State& state)
{
    const auto num = numerology::preset("paper");
    const auto geo = geometry::preset("paper");
    kernel::extended_scene k(num, geo, scene(), { map256(256) });
    scene scn;
    for (std::size_t i = 0; i < k.num_scatterers(); i++) {
        const auto a = k.scatterer_amplitude(i);
        scn.targets.emplace_back(k.scatterer_x(i), k.scatterer_y(i), std::norm(a), std::arg(a));
    }
    kernel::scene_echo e(num, geo, scn);
    std::vector<gr_complex> h(num.num_subcarriers);
    std::uint64_t m = 0;
    for (auto _ : state) {
        e.reference(m, h.data());
        benchmark::DoNotOptimize(h.data());
        m = (m + 1) % 48000;
    }
    state.SetItemsProcessed(state.iterations() * num.num_subcarriers);
}
BENCHMARK(BM_SceneEchoSameScatterers)->Unit(benchmark::kMillisecond)->Iterations(3);

} // namespace

BENCHMARK_MAIN();
