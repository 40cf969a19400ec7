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

void run(benchmark::State& state, filter_type type, bool estimate)
{
    const std::size_t n = state.range(0);
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<gr_complex> y(n), s(n), out(n);
    for (std::size_t i = 0; i < n; i++) {
        y[i] = gr_complex(g(rng), g(rng));
        s[i] = gr_complex(g(rng), g(rng));
    }
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
