/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Pixels per second of image_sink's kernel: dB levels alone, PNG encoding (grey / viridis,
// zlib levels 1 and 6) and the whole write of .npy + .png into /tmp, against image size.

#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/image_file.h>
#include <unistd.h>
#include <filesystem>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {
// A focused-image-like picture: Rayleigh clutter plus a few bright points.
std::vector<gr_complex> picture(size_t rows, size_t cols)
{
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(rows * cols);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    for (size_t i = 0; i < x.size(); i += x.size() / 7)
        x[i] *= 10.0f; // 20 dB above the clutter: most pixels within the 40 dB range
    return x;
}
} // namespace

static void BM_db_levels(benchmark::State& state)
{
    const size_t rows = state.range(0), cols = state.range(1);
    const auto x = picture(rows, cols);
    std::vector<std::uint8_t> lv(x.size());
    for (auto _ : state) {
        kernel::db_levels(x.data(), x.size(), 40.0, lv.data());
        benchmark::DoNotOptimize(lv.data());
    }
    state.SetItemsProcessed(state.iterations() * x.size());
}
BENCHMARK(BM_db_levels)->Args({ 256, 256 })->Args({ 1024, 512 });

static void BM_encode_png(benchmark::State& state)
{
    const size_t rows = state.range(0), cols = state.range(1);
    const unsigned channels = static_cast<unsigned>(state.range(2));
    const int level = static_cast<int>(state.range(3));
    const auto x = picture(rows, cols);
    std::vector<std::uint8_t> lv(x.size());
    kernel::db_levels(x.data(), x.size(), 40.0, lv.data());
    const auto lut = kernel::colormap_table(image_colormap::VIRIDIS);
    std::vector<std::uint8_t> rgb(3 * x.size());
    for (size_t i = 0; i < x.size(); ++i)
        for (int ch = 0; ch < 3; ++ch)
            rgb[3 * i + ch] = lut[lv[i]][ch];
    size_t bytes = 0;
    for (auto _ : state) {
        const auto png = kernel::encode_png(channels == 1 ? lv.data() : rgb.data(),
                                            static_cast<unsigned>(cols),
                                            static_cast<unsigned>(rows),
                                            channels,
                                            level);
        bytes = png.size();
        benchmark::DoNotOptimize(png.data());
    }
    state.SetItemsProcessed(state.iterations() * x.size());
    state.counters["png_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_encode_png)
    ->Args({ 1024, 512, 1, 1 })
    ->Args({ 1024, 512, 1, 6 })
    ->Args({ 1024, 512, 3, 1 })
    ->Args({ 1024, 512, 3, 6 });

static void BM_write_npy_png(benchmark::State& state)
{
    const size_t rows = state.range(0), cols = state.range(1);
    const auto x = picture(rows, cols);
    const auto dir = std::filesystem::temp_directory_path() /
                     ("nrsar_bench_image_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    kernel::image_file_config c;
    c.prefix = (dir / "img").string();
    c.keep = 2;
    kernel::image_writer w(c);
    std::uint64_t n = 0;
    for (auto _ : state)
        w.write(x.data(), rows, cols, n++);
    state.SetItemsProcessed(state.iterations() * x.size());
    std::filesystem::remove_all(dir);
}
BENCHMARK(BM_write_npy_png)->Args({ 1024, 512 })->Unit(benchmark::kMillisecond);
