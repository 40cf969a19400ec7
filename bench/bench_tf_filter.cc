/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of the TF filter kernel at the paper's vlen (items = OFDM symbols of 3333 REs).

#include <gnuradio/nrsar/kernel/tf_filter.h>
#include <benchmark/benchmark.h>
#include <random>
#include <vector>

using namespace gr::nrsar;

namespace {

// Gaussian echo y and reference s of n REs (fixed seed).
void random_pair(std::size_t n, std::vector<gr_complex>& y, std::vector<gr_complex>& s)
{
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    y.resize(n);
    s.resize(n);
    for (std::size_t i = 0; i < n; i++) {
        y[i] = gr_complex(g(rng), g(rng));
        s[i] = gr_complex(g(rng), g(rng));
    }
}

void run(benchmark::State& state, filter_type type, bool estimate)
{
    const std::size_t n = state.range(0);
    std::vector<gr_complex> y, s, out(n);
    random_pair(n, y, s);
    kernel::tf_filter f(n, type, 5.0, estimate);
    for (auto _ : state) {
        f.process(y.data(), s.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["REs/s"] =
        benchmark::Counter(double(state.iterations()) * n, benchmark::Counter::kIsRate);
}

void BM_tf_filter_rf(benchmark::State& s) { run(s, filter_type::RF, false); }
void BM_tf_filter_mf(benchmark::State& s) { run(s, filter_type::MF, false); }
void BM_tf_filter_wf(benchmark::State& s) { run(s, filter_type::WF, false); }
void BM_tf_filter_wf_estimate(benchmark::State& s) { run(s, filter_type::WF, true); }

} // namespace

BENCHMARK(BM_tf_filter_rf)->Arg(3333);
BENCHMARK(BM_tf_filter_mf)->Arg(3333);
BENCHMARK(BM_tf_filter_wf)->Arg(3333);
BENCHMARK(BM_tf_filter_wf_estimate)->Arg(3333);

namespace {
// The WF strategy alone (|s|^2 given): compare with a fused scalar loop (docs).
void BM_wf_apply_only(benchmark::State& state)
{
    const std::size_t n = state.range(0);
    std::vector<gr_complex> y, s, out(n);
    random_pair(n, y, s);
    std::vector<float> m(n);
    for (std::size_t i = 0; i < n; i++)
        m[i] = std::norm(s[i]);
    kernel::wf_filter f(3.16);
    for (auto _ : state) {
        f.apply(y.data(), s.data(), m.data(), out.data(), n);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}

// The same arithmetic as one fused loop, as GCC vectorises it without -march flags.
void BM_wf_fused_loop(benchmark::State& state)
{
    const std::size_t n = state.range(0);
    std::vector<gr_complex> y, s, out(n);
    random_pair(n, y, s);
    const float c = 1.0f / 3.16f;
    for (auto _ : state) {
        const float* yp = reinterpret_cast<const float*>(y.data());
        const float* sp = reinterpret_cast<const float*>(s.data());
        float* op = reinterpret_cast<float*>(out.data());
        for (std::size_t i = 0; i < n; i++) {
            const float yr = yp[2 * i], yi = yp[2 * i + 1], sr = sp[2 * i], si = sp[2 * i + 1];
            const float w = 1.0f / (sr * sr + si * si + c);
            op[2 * i] = (yr * sr + yi * si) * w;
            op[2 * i + 1] = (yi * sr - yr * si) * w;
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}
} // namespace

BENCHMARK(BM_wf_apply_only)->Arg(3333);
BENCHMARK(BM_wf_fused_loop)->Arg(3333);

// Constant-modulus reference (QPSK, |s|^2 = 1): the shortcut (one conj multiply + one real
// scale) against the general per-RE weights on the same data (range(1) = 1: shortcut on).
namespace {
void BM_tf_filter_qpsk(benchmark::State& state, filter_type type)
{
    const std::size_t n = state.range(0);
    std::vector<gr_complex> y, s, out(n);
    random_pair(n, y, s);
    const float a = 0.70710678f;
    for (auto& v : s)
        v = gr_complex(v.real() < 0 ? -a : a, v.imag() < 0 ? -a : a);
    kernel::tf_filter f(n, type, 5.0, false);
    f.set_constant_modulus_path(state.range(1) != 0);
    for (auto _ : state) {
        f.process(y.data(), s.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations());
}
void BM_tf_filter_qpsk_wf(benchmark::State& s) { BM_tf_filter_qpsk(s, filter_type::WF); }
void BM_tf_filter_qpsk_rf(benchmark::State& s) { BM_tf_filter_qpsk(s, filter_type::RF); }
void BM_tf_filter_qpsk_mf(benchmark::State& s) { BM_tf_filter_qpsk(s, filter_type::MF); }
} // namespace

BENCHMARK(BM_tf_filter_qpsk_wf)->Args({ 3333, 0 })->Args({ 3333, 1 });
BENCHMARK(BM_tf_filter_qpsk_rf)->Args({ 3333, 0 })->Args({ 3333, 1 });
BENCHMARK(BM_tf_filter_qpsk_mf)->Args({ 3333, 0 })->Args({ 3333, 1 });
