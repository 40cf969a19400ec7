/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Resource elements per second of the transmit-grid kernels (paper numerology, N = 3333).
// Real time for the paper numerology is 24,000 symbols/s = 80.0 M REs/s.

#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <vector>

using namespace gr::nrsar;

static void BM_gold_sequence_packed(benchmark::State& state)
{
    kernel::gold_sequence g(12345);
    std::vector<std::uint8_t> bytes(3333);
    for (auto _ : state) {
        g.generate_packed(bytes.data(), bytes.size());
        benchmark::DoNotOptimize(bytes.data());
    }
    state.SetItemsProcessed(state.iterations() * 8 * static_cast<int64_t>(bytes.size()));
    state.SetLabel("bits/s");
}
BENCHMARK(BM_gold_sequence_packed);

static void BM_constellation_map(benchmark::State& state)
{
    const auto mod = static_cast<modulation>(state.range(0));
    kernel::constellation c(mod);
    const std::size_t nsym = 3333;
    std::vector<std::uint8_t> bytes(nsym + 8, 0x5a);
    std::vector<gr_complex> out(nsym);
    for (auto _ : state) {
        c.map_packed(bytes.data(), 0, nsym, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(nsym));
}
BENCHMARK(BM_constellation_map)
    ->Arg(static_cast<int>(modulation::QPSK))
    ->Arg(static_cast<int>(modulation::QAM64))
    ->Arg(static_cast<int>(modulation::QAM256));

// A full column from the PRBS, as nr_isac_tx does it without payload.
static void BM_nr_grid_prbs_column(benchmark::State& state)
{
    const auto mod = static_cast<modulation>(state.range(0));
    const auto mode = static_cast<tx_mode>(state.range(1));
    kernel::nr_grid g(numerology::preset("paper"), mod, mode, srs_config());
    kernel::gold_sequence prbs(1);
    const unsigned n = g.num_subcarriers();
    std::vector<std::uint8_t> bytes(n + 8);
    std::vector<gr_complex> out(n);
    std::uint64_t m = 0;
    for (auto _ : state) {
        const std::size_t nbytes = (g.data_bits(m) + 7) / 8;
        prbs.generate_packed(bytes.data(), nbytes);
        g.fill(m, bytes.data(), 0, out.data());
        benchmark::DoNotOptimize(out.data());
        m++;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
}
BENCHMARK(BM_nr_grid_prbs_column)
    ->Args({ static_cast<int>(modulation::QAM256), static_cast<int>(tx_mode::DATA) })
    ->Args({ static_cast<int>(modulation::QAM64), static_cast<int>(tx_mode::DATA) })
    ->Args({ static_cast<int>(modulation::QAM256), static_cast<int>(tx_mode::DATA_SRS) });
