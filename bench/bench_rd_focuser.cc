/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Focused lines per second of kernel::rd_focuser against K (range bins) and M (lines per
// block), scene band (a 10 % band, RCMC on) versus the full PRF band.

#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/rd_focuser.h>
#include <random>
#include <vector>

using gr::nrsar::doppler_band;
using gr::nrsar::focuser_config;
using gr::nrsar::kernel::rd_block;
using gr::nrsar::kernel::rd_focuser;

// K range bins x M lines at the presummed paper rate, a 10 % band.
static rd_block paper_block(unsigned K, unsigned M)
{
    rd_block b;
    b.num_range_bins = K;
    b.num_lines = M;
    b.pulse_interval_s = 1.0 / 2400.0; // presummed paper rate
    b.velocity_mps = 50.0;
    b.wavelength_m = 0.0857;
    b.first_range_m = 1000.0;
    b.range_bin_m = 1.5;
    b.band_lo_hz = -20.0;
    b.band_hi_hz = 220.0; // 10 % of the PRF
    b.range_centre_cycles = 0.4;
    return b;
}

// K x M complex Gaussian samples (seeded: every benchmark focuses the same data).
static std::vector<gr_complex> gaussian_block(unsigned K, unsigned M)
{
    std::mt19937 rng(1);
    std::normal_distribution<float> g;
    std::vector<gr_complex> in(static_cast<size_t>(K) * M);
    for (auto& x : in)
        x = gr_complex(g(rng), g(rng));
    return in;
}

static void run(benchmark::State& state, doppler_band band, bool rcmc)
{
    const unsigned K = static_cast<unsigned>(state.range(0));
    const unsigned M = static_cast<unsigned>(state.range(1));
    const rd_block b = paper_block(K, M);
    focuser_config cfg;
    cfg.band = band;
    cfg.rcmc = rcmc;
    cfg.rcmc_skip_below_bins = 0.0;
    rd_focuser f(cfg, b);
    const std::vector<gr_complex> in = gaussian_block(K, M);
    std::vector<gr_complex> out(in.size());
    for (auto _ : state) {
        f.focus(in.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * M);
    state.counters["band_bins"] = f.band_bins();
    state.counters["fft_size"] = f.fft_size();
}

static void BM_scene_band(benchmark::State& s) { run(s, doppler_band::SCENE, true); }
static void BM_full_band(benchmark::State& s) { run(s, doppler_band::FULL, true); }
static void BM_scene_band_no_rcmc(benchmark::State& s) { run(s, doppler_band::SCENE, false); }

#define SIZES Args({ 128, 2400 })->Args({ 64, 4800 })->Args({ 256, 4800 })->Args({ 512, 4800 })->Args({ 256, 1024 })->Args({ 256, 16384 })
BENCHMARK(BM_scene_band)->SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_full_band)->SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_scene_band_no_rcmc)->SIZES->Unit(benchmark::kMillisecond);

// The range-Doppler map output (rd_focuser's rd_map port): the same block from range-major
// input without the map (what the block does when the port is unconnected) and with it.
static void run_range_major(benchmark::State& state, bool map)
{
    const unsigned K = static_cast<unsigned>(state.range(0));
    const unsigned M = static_cast<unsigned>(state.range(1));
    const rd_block b = paper_block(K, M);
    focuser_config cfg;
    cfg.rcmc_skip_below_bins = 0.0;
    rd_focuser f(cfg, b);
    const std::vector<gr_complex> in = gaussian_block(K, M);
    std::vector<gr_complex> out(in.size());
    std::vector<gr_complex> rd(static_cast<size_t>(f.fft_size()) * K);
    for (auto _ : state) {
        f.focus_range_major(in.data(), M, out.data(), 0, M, map ? rd.data() : nullptr);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * M);
    state.counters["band_bins"] = f.band_bins();
}
static void BM_range_major(benchmark::State& s) { run_range_major(s, false); }
static void BM_range_major_rd_map(benchmark::State& s) { run_range_major(s, true); }
BENCHMARK(BM_range_major)->Args({ 256, 4800 })->Unit(benchmark::kMillisecond);
BENCHMARK(BM_range_major_rd_map)->Args({ 256, 4800 })->Unit(benchmark::kMillisecond);
