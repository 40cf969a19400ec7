/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Back-projections per second (pixels x pulses / s) of kernel::bp_focuser: one aperture of
// P pulses onto a (P / line step)-line x K-bin image at the presummed paper geometry, against
// the upsampling factor U, one or two threads, the AVX2/FMA and the generic inner loop.

#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/bp_focuser.h>
#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

using gr::nrsar::kernel::bp_focuser;
using gr::nrsar::kernel::bp_grid;

namespace {
constexpr double T = 1.0 / 2400.0, v = 50.0; // presummed paper rate

bp_grid bench_grid(unsigned K, unsigned P, unsigned U, unsigned step)
{
    bp_grid g;
    g.num_range_bins = K;
    g.first_range_m = 1000.0;
    g.range_bin_m = 1.1;
    g.wavelength_m = 0.0857;
    g.range_centre_cycles = 0.4;
    g.upsample = U;
    g.num_lines = P / step;
    g.line_step = step;
    g.first_y_m = 50.0;
    g.line_spacing_m = v * T;
    g.reference_height_m = 1000.0 * 0.7;
    g.beam_oversample = 8.0;
    return g;
}

// Seeded: every benchmark projects the same data.
struct aperture {
    std::vector<gr_complex> pulses;
    std::vector<std::array<double, 3>> antenna;
    aperture(unsigned K, unsigned P) : pulses(size_t(K) * P), antenna(P)
    {
        std::mt19937 rng(1);
        std::normal_distribution<float> gauss;
        for (auto& x : pulses)
            x = gr_complex(gauss(rng), gauss(rng));
        for (unsigned p = 0; p < P; ++p)
            antenna[p] = { 0.0, v * T * p, 700.0 };
    }
};

void focus(bp_focuser& bp, const aperture& a, std::vector<gr_complex>& img)
{
    bp.reset(50.0);
    bp.add(a.pulses.data(), static_cast<unsigned>(a.antenna.size()), a.antenna.data());
    bp.image(img.data());
}
} // namespace

static void run(benchmark::State& state, bool simd)
{
    const unsigned K = static_cast<unsigned>(state.range(0));
    const unsigned P = static_cast<unsigned>(state.range(1)); // pulses = image lines
    const unsigned U = static_cast<unsigned>(state.range(2));
    const unsigned threads = static_cast<unsigned>(state.range(3));
    const unsigned taps = state.range(4); // short sinc (0: upsampled linear)
    const unsigned sub = state.range(5);  // FFBP subaperture (0: exact BP)
    const unsigned step = state.range(6); // a line every step pulses
    bp_grid g = bench_grid(K, P, U, step);
    g.sinc_taps = taps;
    g.subaperture = sub;
    bp_focuser bp(g, threads, simd);
    const aperture a(K, P);
    std::vector<gr_complex> img(size_t(K) * g.num_lines);
    for (auto _ : state) {
        focus(bp, a, img);
        benchmark::DoNotOptimize(img.data());
    }
    state.counters["bp_per_s"] = benchmark::Counter(
        double(K) * P * g.num_lines * state.iterations(), benchmark::Counter::kIsRate);
    state.counters["simd"] = bp.simd();
    state.counters["beams"] = bp.beams();
}

// Recursive FFBP against two-level FFBP and exact BP in one run: K, pulses (= lines),
// threads, subaperture L (0: exact BP), levels, merge factor, beam oversampling; U = 8.
// nmse_db: the image against exact BP's of the same data over the bins more than 16 from
// the window's ends (white data fills the range band, so U = 8 adds its own -44 dB per
// interpolation).
static void BM_ffbp_levels(benchmark::State& state)
{
    const unsigned K = static_cast<unsigned>(state.range(0));
    const unsigned P = static_cast<unsigned>(state.range(1));
    const unsigned threads = static_cast<unsigned>(state.range(2));
    bp_grid g = bench_grid(K, P, 8, 1);
    g.subaperture = static_cast<unsigned>(state.range(3));
    g.levels = static_cast<unsigned>(state.range(4));
    g.merge_factor = static_cast<unsigned>(state.range(5));
    g.beam_oversample = static_cast<double>(state.range(6));
    const aperture a(K, P);
    static std::vector<gr_complex> exact; // of the last (K, P)
    static size_t exact_size = 0;
    if (exact_size != size_t(K) * P) {
        exact.assign(size_t(K) * P, gr_complex(0.0f, 0.0f));
        bp_focuser ref(bench_grid(K, P, 8, 1), 2);
        focus(ref, a, exact);
        exact_size = exact.size();
    }
    bp_focuser bp(g, threads);
    std::vector<gr_complex> img(size_t(K) * P);
    for (auto _ : state) {
        focus(bp, a, img);
        benchmark::DoNotOptimize(img.data());
    }
    double err = 0.0, ref = 0.0;
    for (unsigned j = 0; j < P; ++j)
        for (unsigned k = 16; k + 16 < K; ++k) {
            const size_t i = size_t(j) * K + k;
            err += std::norm(std::complex<double>(img[i]) - std::complex<double>(exact[i]));
            ref += std::norm(std::complex<double>(exact[i]));
        }
    state.counters["nmse_db"] = 10.0 * std::log10(err / ref);
    state.counters["beams"] = bp.beams();
}

static void BM_bp_simd(benchmark::State& s) { run(s, true); }
static void BM_bp_generic(benchmark::State& s) { run(s, false); }

// K, pulses, U, threads, sinc taps, FFBP subaperture, line step (bp_per_s counts the exact
// BP's K P^2 / step back-projections, so FFBP's is its equivalent rate).
BENCHMARK(BM_bp_simd)
    ->Args({ 256, 512, 8, 1, 0, 0, 1 })
    ->Args({ 256, 512, 8, 2, 0, 0, 1 })
    ->Args({ 256, 512, 2, 1, 0, 0, 1 })
    ->Args({ 256, 512, 32, 1, 0, 0, 1 })
    ->Args({ 256, 512, 8, 1, 8, 0, 1 })
    ->Args({ 256, 512, 8, 1, 16, 0, 1 })
    ->Args({ 256, 512, 8, 1, 0, 16, 1 })
    ->Args({ 256, 512, 8, 1, 0, 32, 1 })
    ->Args({ 256, 512, 8, 1, 0, 64, 1 })
    // The paper-full aperture (4800 presummed pulses, both cores): FFBP onto 4800 lines,
    // exact BP onto 4800 lines and onto every 8th (0.167 m: 1.9 lines per azimuth
    // resolution v / B = 0.32 m of the paper scene's 155 Hz Doppler band).
    ->Args({ 256, 4800, 8, 2, 0, 64, 1 })
    ->Args({ 256, 4800, 8, 2, 0, 0, 1 })
    ->Args({ 256, 4800, 8, 2, 0, 0, 8 })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_bp_generic)
    ->Args({ 256, 512, 8, 1, 0, 0, 1 })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ffbp_levels)
    ->Args({ 256, 512, 1, 0, 1, 4, 8 })
    ->Args({ 256, 512, 1, 64, 1, 4, 8 })
    ->Args({ 256, 512, 1, 16, 3, 4, 8 })
    ->Args({ 256, 512, 1, 8, 4, 2, 8 })
    ->Args({ 256, 4800, 2, 0, 1, 4, 8 })
    ->Args({ 256, 4800, 2, 64, 1, 4, 8 })
    ->Args({ 256, 4800, 2, 16, 3, 4, 8 })
    ->Args({ 256, 4800, 2, 16, 3, 4, 16 })
    ->Args({ 256, 4800, 2, 16, 4, 4, 8 })
    ->Args({ 256, 4800, 2, 8, 5, 2, 8 })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
