/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Throughput of the CP-OFDM modem kernels (items = samples of the time-domain stream) at the
// paper (3333 of 4096, CP 1024) and sdr20 (612 of 1024, CP 256) numerologies, the
// Schmidl & Cox search and the CFO derotator.

#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include "../tests/test_util.h"
#include <benchmark/benchmark.h>
#include <vector>

using namespace gr::nrsar;

namespace {

void BM_ofdm_modulator(benchmark::State& state)
{
    const unsigned n = state.range(0), f = state.range(1), cp = state.range(2);
    const auto s = nrsar_test::gaussian_samples(n, 1);
    kernel::ofdm_modulator mod(n, f, cp, (n / 2) & ~1u);
    std::vector<gr_complex> out(mod.symbol_length());
    for (auto _ : state) {
        mod.execute(s.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * mod.symbol_length());
}

void BM_ofdm_demodulator(benchmark::State& state)
{
    const unsigned n = state.range(0), f = state.range(1), cp = state.range(2);
    const auto x = nrsar_test::gaussian_samples(f + cp, 2);
    kernel::ofdm_demodulator dem(n, f, cp, (n / 2) & ~1u, cp);
    std::vector<gr_complex> out(n);
    for (auto _ : state) {
        dem.execute(x.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * dem.symbol_length());
}

// The receive path's demodulator with its finite check, one symbol (arg 0) or symbols in
// turn from 512 (arg 1: 18 MB at paper, every symbol comes from memory): the guard's own
// pass then the copy into the FFT (as ofdm_demod ran before issue 16), against the check
// carried by the copy (execute_if_finite).
void demod_checked(benchmark::State& state, bool one_pass)
{
    const unsigned n = 3333, f = 4096, cp = 288;
    const std::size_t m = state.range(0) ? 512 : 1, len = f + cp;
    const auto x = nrsar_test::gaussian_samples(m * len, 2);
    kernel::ofdm_demodulator dem(n, f, cp, (n / 2) & ~1u, cp / 2);
    kernel::finite_guard guard;
    std::vector<gr_complex> out(n);
    std::size_t i = 0;
    for (auto _ : state) {
        const gr_complex* in = &x[i * len];
        if (one_pass) {
            dem.execute_if_finite(in, out.data());
        } else {
            std::size_t bad = 0;
            dem.execute(guard.guard(in, len, bad), out.data());
        }
        benchmark::DoNotOptimize(out.data());
        i = (i + 1) % m;
    }
    state.SetItemsProcessed(state.iterations() * len);
}
void BM_ofdm_demod_guard_then_copy(benchmark::State& s) { demod_checked(s, false); }
void BM_ofdm_demod_checked_copy(benchmark::State& s) { demod_checked(s, true); }

// Search over noise (never locks): the cost per sample before acquisition.
void BM_sc_search(benchmark::State& state)
{
    const unsigned f = state.range(1), cp = state.range(2);
    const std::size_t chunk = 65536;
    const auto x = nrsar_test::gaussian_samples(chunk, 3);
    kernel::sc_acquirer acq(f, cp, 0.3, 3 * (f + cp));
    for (auto _ : state)
        benchmark::DoNotOptimize(acq.push(x.data(), chunk));
    state.SetItemsProcessed(state.iterations() * chunk);
}

void BM_phase_rotator(benchmark::State& state)
{
    const std::size_t chunk = 65536;
    const auto x = nrsar_test::gaussian_samples(chunk, 4);
    std::vector<gr_complex> out(chunk);
    kernel::phase_rotator rot(0.001234);
    for (auto _ : state) {
        rot.rotate(x.data(), out.data(), chunk);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * chunk);
}

} // namespace

BENCHMARK(BM_ofdm_modulator)->Args({ 3333, 4096, 1024 })->Args({ 612, 1024, 256 });
BENCHMARK(BM_ofdm_demodulator)->Args({ 3333, 4096, 1024 })->Args({ 612, 1024, 256 });
BENCHMARK(BM_ofdm_demod_guard_then_copy)->Arg(0)->Arg(1);
BENCHMARK(BM_ofdm_demod_checked_copy)->Arg(0)->Arg(1);
BENCHMARK(BM_sc_search)->Args({ 3333, 4096, 1024 })->Args({ 612, 1024, 256 });
BENCHMARK(BM_phase_rotator);
