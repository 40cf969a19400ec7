/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of the point-target metrics per aperture (pixels/s), image + reference given,
// and of the analytic PSF model that replaces the reference input.

#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {
struct fixture {
    std::vector<gr_complex> img, ref;
    fixture(int lines, int bins) : img(std::size_t(lines) * bins), ref(img.size())
    {
        kernel::psf_model(ref.data(), lines, bins, lines / 2 + 0.3, bins / 2 + 0.4, 8.0,
                          lines / 8.0, 1.0, bins, 0.05, 0.0);
        std::mt19937 rng(1);
        std::normal_distribution<float> g(0.0f, 0.01f);
        for (std::size_t i = 0; i < img.size(); ++i)
            img[i] = 0.9f * ref[i] + gr_complex(g(rng), g(rng));
    }
};
} // namespace

static void BM_image_metrics(benchmark::State& state)
{
    const int lines = state.range(0), bins = state.range(1);
    fixture f(lines, bins);
    kernel::image_metrics im;
    kernel::metrics_config cfg;
    cfg.azimuth_res_lines = 8.0;
    // FFT plans of the cut interpolation are made once per cut length: not measured.
    im.compute(f.img.data(), f.ref.data(), lines, bins, lines / 2, bins / 2, cfg);
    for (auto _ : state) {
        auto r = im.compute(f.img.data(), f.ref.data(), lines, bins, lines / 2, bins / 2, cfg);
        benchmark::DoNotOptimize(r);
    }
    state.SetItemsProcessed(state.iterations() * int64_t(lines) * bins);
}
BENCHMARK(BM_image_metrics)->Args({ 480, 512 })->Args({ 4800, 512 })->Unit(benchmark::kMillisecond);

static void BM_psf_model(benchmark::State& state)
{
    const int lines = state.range(0), bins = state.range(1);
    std::vector<gr_complex> out(std::size_t(lines) * bins);
    for (auto _ : state) {
        kernel::psf_model(out.data(), lines, bins, lines / 2 + 0.3, bins / 2 + 0.4, 8.0,
                          lines / 8.0, 1.0, bins, 0.05, 0.0);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(lines) * bins);
}
BENCHMARK(BM_psf_model)->Args({ 4800, 512 })->Unit(benchmark::kMillisecond);
