/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The TF filter and range IFFT of one paper symbol (N 3333 -> 3360 points, WF, Hann,
// 90 bins kept; items = symbols), fused (range_compress) against the two kernels in turn,
// and the bare 3360-point transform. Arg 0: the same symbol every time (hot caches); arg 1:
// symbols taken in turn from rings of 512, as a flowgraph's 3333-wide buffers hold them
// (13.6 MB per stream: every symbol comes from memory).

#include <gnuradio/nrsar/kernel/range_compress.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;
using win = gr::fft::window;

namespace {

constexpr unsigned n = 3333, nfft = 3360, first = 1500, count = 90;
constexpr std::size_t ring = 512; // GNU Radio's buffer of 3333-complex items

std::vector<gr_complex> symbols(std::size_t m, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> x(m * n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

kernel::tf_filter make_filter() { return kernel::tf_filter(n, filter_type::WF, -20.0, false); }
kernel::range_ifft make_ifft()
{
    return kernel::range_ifft(n, nfft, win::WIN_HANN, win::INVALID_WIN_PARAM, first, count);
}

void BM_rx_separate(benchmark::State& state)
{
    const std::size_t m = state.range(0) ? ring : 1;
    const auto y = symbols(m, 1), s = symbols(m, 2);
    std::vector<gr_complex> mid(m * n), out(count);
    auto filter = make_filter();
    auto ifft = make_ifft();
    std::size_t i = 0;
    for (auto _ : state) {
        filter.process(&y[i * n], &s[i * n], &mid[i * n]);
        ifft.execute(&mid[i * n], out.data());
        benchmark::DoNotOptimize(out.data());
        i = (i + 1) % m;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_rx_fused(benchmark::State& state)
{
    const std::size_t m = state.range(0) ? ring : 1;
    const auto y = symbols(m, 1), s = symbols(m, 2);
    std::vector<gr_complex> out(count);
    kernel::range_compress fused(make_filter(), make_ifft());
    std::size_t i = 0;
    for (auto _ : state) {
        fused.process(&y[i * n], &s[i * n], out.data());
        benchmark::DoNotOptimize(out.data());
        i = (i + 1) % m;
    }
    state.SetItemsProcessed(state.iterations());
}

// The floor of both: the 3360-point transform and the crop alone.
void BM_fft_only(benchmark::State& state)
{
    auto ifft = make_ifft();
    std::vector<gr_complex> out(count);
    for (auto _ : state) {
        ifft.transform(out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

// range_ifft alone on symbols from the ring (arg 1) or one symbol (arg 0).
void BM_range_ifft_input(benchmark::State& state)
{
    const std::size_t m = state.range(0) ? ring : 1;
    const auto x = symbols(m, 3);
    std::vector<gr_complex> out(count);
    auto ifft = make_ifft();
    std::size_t i = 0;
    for (auto _ : state) {
        ifft.execute(&x[i * n], out.data());
        benchmark::DoNotOptimize(out.data());
        i = (i + 1) % m;
    }
    state.SetItemsProcessed(state.iterations());
}

} // namespace

BENCHMARK(BM_rx_separate)->Arg(0)->Arg(1);
BENCHMARK(BM_rx_fused)->Arg(0)->Arg(1);
BENCHMARK(BM_fft_only);
BENCHMARK(BM_range_ifft_input)->Arg(0)->Arg(1);
