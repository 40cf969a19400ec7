/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// PUSCH receiver kernel at the paper numerology (N = 3333, 256-QAM, DMRS pusch2): one slot
// = 14 x 3333 REs, 12 x 3333 x 8 = 319,968 coded bits. Real time: 1714 slots/s.
// Items = REs of the slot (all 14 symbols); the label gives the payload bits per slot.

#include <benchmark/benchmark.h>
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <gnuradio/nrsar/kernel/pusch_rx.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <random>
#include <string>
#include <vector>

using namespace gr::nrsar;

namespace {
std::vector<gr_complex> make_slot(const pusch_config& cfg, float noise_std = 0.003f)
{
    const numerology& num = cfg.num;
    const modulation mod = cfg.mod;
    const dmrs_config& dmrs = cfg.dmrs;
    kernel::transport_block_codec codec(cfg);
    std::vector<std::uint8_t> tb(codec.tb_bytes());
    std::mt19937 bytes(3);
    kernel::mac_sdu sdu;
    sdu.filler = false;
    sdu.data.resize(codec.payload_bytes());
    for (auto& b : sdu.data)
        b = static_cast<std::uint8_t>(bytes());
    sdu.write(tb.data(), tb.size());
    std::vector<std::uint8_t> bits(codec.slot_bits());
    codec.encode(tb.data(), 0, 0, bits.data());
    std::vector<std::uint8_t> packed((bits.size() + 7) / 8 + 8, 0);
    for (std::size_t i = 0; i < bits.size(); i++)
        packed[i / 8] |= static_cast<std::uint8_t>(bits[i] << (7 - i % 8));
    kernel::nr_grid grid(num, mod, tx_mode::DATA, srs_config(), dmrs);
    const unsigned n = num.num_subcarriers;
    std::vector<gr_complex> y(static_cast<std::size_t>(num.symbols_per_slot) * n);
    std::size_t pos = 0;
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, noise_std);
    for (unsigned l = 0; l < num.symbols_per_slot; l++) {
        pos = grid.fill(l, packed.data(), pos, y.data() + static_cast<std::size_t>(l) * n);
        for (unsigned k = 0; k < n; k++)
            y[l * n + k] += gr_complex(g(rng), g(rng));
    }
    return y;
}

// Paper numerology, 256-QAM (qam256 MCS 27), pusch2, a random payload at 50 dB SNR.
void run_rx(benchmark::State& state,
            pusch_coding coding,
            unsigned threads = 1,
            const char* preset = "paper",
            float noise_std = 0.003f,
            bool simd = true)
{
    pusch_config cfg;
    cfg.num = numerology::preset(preset);
    cfg.coding = coding;
    const auto y = make_slot(cfg, noise_std);
    kernel::pusch_rx rx(cfg);
    rx.set_threads(threads);
    rx.set_simd(simd);
    bool ok = true;
    double iterations = 0.0;
    for (auto _ : state) {
        const auto r = rx.process(y.data(), 0);
        ok = ok && r.tb.header_ok;
        iterations = r.tb.mean_iterations;
        benchmark::DoNotOptimize(r.snr_db);
    }
    if (!ok)
        state.SkipWithError("CRC failed");
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(y.size()));
    state.counters["payload_Mbit_per_s"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * 8.0 * rx.codec().payload_bytes() / 1e6,
        benchmark::Counter::kIsRate);
    state.counters["ldpc_iterations"] = iterations;
}
} // namespace

static void BM_pusch_rx_uncoded(benchmark::State& state) { run_rx(state, pusch_coding::NONE); }
BENCHMARK(BM_pusch_rx_uncoded)->Unit(benchmark::kMillisecond);

// The same with the equaliser's generic pass (its AVX2 pass off): the ratio of the two is
// what the AVX2 equaliser gains on the whole uncoded receiver.
static void BM_pusch_rx_uncoded_generic_equaliser(benchmark::State& state)
{
    run_rx(state, pusch_coding::NONE, 1, "paper", 0.003f, false);
}
BENCHMARK(BM_pusch_rx_uncoded_generic_equaliser)->Unit(benchmark::kMillisecond);

static void BM_pusch_rx_nr_ldpc(benchmark::State& state)
{
    run_rx(state, pusch_coding::NR_LDPC);
}
BENCHMARK(BM_pusch_rx_nr_ldpc)->Unit(benchmark::kMillisecond);

// The same with the code blocks split over 2 threads (CPU time: the caller's thread only).
static void BM_pusch_rx_nr_ldpc_2threads(benchmark::State& state)
{
    run_rx(state, pusch_coding::NR_LDPC, 2);
}
BENCHMARK(BM_pusch_rx_nr_ldpc_2threads)->Unit(benchmark::kMillisecond)->UseRealTime();

// The base station's numerology: sdr20 (N = 612, C = 7 blocks of BG1 Zc 384) at 30 dB SNR
// per RE (noise std 0.0224 per component), where the decoder runs about 2 iterations per
// block, as in base_station_realtime. Real time: 1714 slots/s, 0.583 ms per slot.
static void BM_pusch_rx_nr_ldpc_sdr20(benchmark::State& state)
{
    run_rx(state, pusch_coding::NR_LDPC, 1, "sdr20", 0.0224f);
}
BENCHMARK(BM_pusch_rx_nr_ldpc_sdr20)->Unit(benchmark::kMicrosecond);

// The max-log demapper alone (3333 x 12 symbols of 256-QAM per iteration).
static void BM_soft_demapper(benchmark::State& state)
{
    const auto mod = static_cast<modulation>(state.range(0));
    kernel::soft_demapper d(mod);
    std::mt19937 rng(2);
    std::normal_distribution<float> g(0.0f, 0.7f);
    std::vector<gr_complex> y(3333 * 12);
    for (auto& v : y)
        v = gr_complex(g(rng), g(rng));
    std::vector<float> nv(y.size(), 0.01f), llr(y.size() * d.bits_per_symbol());
    for (auto _ : state) {
        d.demap(y.data(), nv.data(), y.size(), llr.data());
        benchmark::DoNotOptimize(llr.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(y.size()));
}
BENCHMARK(BM_soft_demapper)
    ->Arg(static_cast<int>(modulation::QPSK))
    ->Arg(static_cast<int>(modulation::QAM256));
