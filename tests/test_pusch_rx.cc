/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "test_util.h"
#include <gnuradio/nrsar/kernel/nr_grid.h>
#include <gnuradio/nrsar/kernel/pusch_rx.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <gtest/gtest.h>
#include <cstring>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

using namespace gr::nrsar;
using namespace gr::nrsar::kernel;

namespace {
// One slot through encode -> grid -> channel h(k) exp(j phi l) + noise -> pusch_rx.
// The qam256 table's highest MCS of each modulation (38.214 Table 5.1.3.1-2).
unsigned top_mcs(modulation m)
{
    switch (m) {
    case modulation::QPSK:
        return 4;
    case modulation::QAM16:
        return 10;
    case modulation::QAM64:
        return 19;
    default:
        return 27;
    }
}

struct loop {
    pusch_config cfg;
    unsigned threads = 1;
    bool simd = true;
    std::vector<gr_complex> eq; // the equalised data REs of the last run
    loop(modulation m, const char* d, pusch_coding coding = pusch_coding::NONE)
    {
        cfg.num = numerology::preset("tiny");
        cfg.mod = m;
        cfg.dmrs = dmrs_config::preset(d);
        cfg.coding = coding;
        cfg.mcs = top_mcs(m);
        cfg.n_id = 9;
    }

    pusch_slot_result run(std::uint64_t slot,
                          const std::vector<std::uint8_t>& payload,
                          double sigma2,
                          double cfo_rad_per_symbol,
                          std::vector<std::uint8_t>* got,
                          double timing_samples = 0.0)
    {
        const numerology& num = cfg.num;
        const unsigned n = num.num_subcarriers, sps = num.symbols_per_slot;
        transport_block_codec codec(cfg);
        mac_sdu sdu;
        sdu.filler = false;
        sdu.data = payload;
        std::vector<std::uint8_t> tb(codec.tb_bytes());
        sdu.write(tb.data(), tb.size());
        std::vector<std::uint8_t> bits(codec.slot_bits());
        codec.encode(tb.data(), 0, slot, bits.data());
        std::vector<std::uint8_t> packed((bits.size() + 7) / 8, 0);
        for (std::size_t i = 0; i < bits.size(); i++)
            packed[i / 8] |= static_cast<std::uint8_t>(bits[i] << (7 - i % 8));
        nr_grid grid(num, cfg.mod, tx_mode::DATA, srs_config(), cfg.dmrs);
        std::vector<gr_complex> y(static_cast<std::size_t>(sps) * n);
        std::size_t pos = 0;
        const auto noise = nrsar_test::gaussian_samples(y.size(), 17);
        for (unsigned l = 0; l < sps; l++) {
            pos = grid.fill(slot * sps + l, packed.data(), pos, y.data() + l * n);
            for (unsigned k = 0; k < n; k++) {
                // smooth frequency response (two paths, delays 0.4 and 0.9 samples of the
                // 64-point grid) and a common phase drift
                const double f = static_cast<double>(k) / n;
                const std::complex<double> h =
                    (0.9 * std::polar(1.0, -2 * M_PI * 0.4 * f) +
                     0.3 * std::polar(1.0, -2 * M_PI * 0.9 * f + 1.0)) *
                    std::polar(1.0, cfo_rad_per_symbol * l) *
                    // FFT window timing_samples early (ofdm_sync's backoff): linear phase
                    std::polar(1.0,
                               -2 * M_PI * (static_cast<double>(k) - num.dc_subcarrier()) *
                                   timing_samples / num.fft_size);
                const std::complex<double> v =
                    h * std::complex<double>(y[l * n + k]) +
                    std::sqrt(sigma2 / 2.0) * std::complex<double>(noise[l * n + k]);
                y[l * n + k] = gr_complex(static_cast<float>(v.real()), static_cast<float>(v.imag()));
            }
        }
        EXPECT_EQ(pos, bits.size());
        pusch_rx rx(cfg);
        rx.set_threads(threads);
        rx.set_simd(simd);
        eq.assign(rx.data_res(), gr_complex(0.0f, 0.0f));
        auto res = rx.process(y.data(), slot, eq.data());
        if (got)
            *got = res.tb.sdu.data;
        return res;
    }
};
} // namespace

TEST(pusch_rx, decodes_through_channel_and_phase_drift)
{
    std::mt19937 rng(1);
    for (const char* d : { "pusch1", "pusch2", "pusch4" })
        for (auto mod : { modulation::QPSK, modulation::QAM64, modulation::QAM256 })
            for (auto coding : { pusch_coding::NONE, pusch_coding::NR_LDPC }) {
            loop lp(mod, d, coding);
            std::vector<std::uint8_t> payload(50), got;
            for (auto& b : payload)
                b = static_cast<std::uint8_t>(rng());
            // one DMRS symbol cannot follow a drift: give it none
            const double drift = std::string(d) == "pusch1" ? 0.0 : 0.02;
            const auto res = lp.run(21, payload, 1e-5, drift, &got);
            EXPECT_TRUE(res.tb.header_ok) << d << " " << static_cast<int>(mod);
            EXPECT_EQ(got, payload);
            // noise from the empty odd DMRS subcarriers: 1e-5 within the sampling spread
            EXPECT_NEAR(res.noise_var, 1e-5, 0.35e-5);
            EXPECT_TRUE(res.tb_final);
            EXPECT_EQ(res.transmissions, 1u);
            }
}

// ofdm_sync's backoff (b samples of the CP) turns the phase by 4 pi b / F between
// neighbouring DMRS REs; b = 2 of F = 64 is the paper's 128 of 4096 (0.39 rad). The
// estimate removes the common phase step before its straight-line fit (without that the
// fit shrinks |h| by (1 + 2 cos 0.39) / 3: EVM about -24 dB, 256-QAM fails).
TEST(pusch_rx, phase_slope_of_an_early_fft_window)
{
    std::mt19937 rng(3);
    for (const double b : { 2.0, -3.0, 6.0 }) {
        loop lp(modulation::QAM256, "pusch2");
        std::vector<std::uint8_t> payload(50), got;
        for (auto& v : payload)
            v = static_cast<std::uint8_t>(rng());
        const auto res = lp.run(3, payload, 1e-5, 0.0, &got, b);
        EXPECT_TRUE(res.tb.header_ok) << b;
        EXPECT_EQ(got, payload);
        EXPECT_LT(res.evm_db, -35.0) << b;
    }
}

TEST(pusch_rx, ldpc_loop_and_low_snr_failure)
{
    loop lp(modulation::QPSK, "pusch2", pusch_coding::NR_LDPC);
    std::vector<std::uint8_t> payload(20, 0xa5), got;
    EXPECT_TRUE(lp.run(3, payload, 1e-3, 0.0, &got).tb.header_ok);
    EXPECT_EQ(got, payload);
    const auto bad = lp.run(3, payload, 10.0, 0.0, &got);
    EXPECT_FALSE(bad.tb.header_ok);
    EXPECT_TRUE(got.empty());
}

TEST(pusch_rx, two_threads_decode_the_same_code_blocks)
{
    // sdr20: several code blocks, split over two threads; at an SNR where the LDPC needs
    // more than one iteration the two runs must agree in every output
    loop lp(modulation::QAM256, "pusch2", pusch_coding::NR_LDPC);
    lp.cfg.num = numerology::preset("sdr20");
    const transport_block_codec codec(lp.cfg);
    ASSERT_GE(codec.code_blocks(), 2u);
    std::vector<std::uint8_t> payload(codec.payload_bytes());
    for (std::size_t i = 0; i < payload.size(); i++)
        payload[i] = static_cast<std::uint8_t>(i * 131 + 7);
    std::vector<std::uint8_t> got1, got2;
    const auto one = lp.run(1, payload, 1.5e-3, 0.0, &got1);
    lp.threads = 2;
    const auto two = lp.run(1, payload, 1.5e-3, 0.0, &got2);
    EXPECT_TRUE(one.tb.header_ok);
    EXPECT_GT(one.tb.mean_iterations, 1.0);
    EXPECT_EQ(got1, payload);
    EXPECT_EQ(got2, got1);
    EXPECT_EQ(two.tb.header_ok, one.tb.header_ok);
    EXPECT_EQ(two.tb.cb_crc_ok, one.tb.cb_crc_ok);
    EXPECT_EQ(two.tb.mean_iterations, one.tb.mean_iterations);
    EXPECT_EQ(two.snr_db, one.snr_db);
    EXPECT_EQ(two.evm_db, one.evm_db);
}

TEST(pusch_rx, avx2_and_generic_equalisers_agree)
{
    // The equaliser's AVX2 pass (8 REs at a time, a generic tail) and the generic pass give
    // the same floats, so the same LLRs and decisions: tiny (N = 64, no tail) and paper
    // (N = 3333: 416 groups of 8 and a tail of 5).
    for (const char* preset : { "tiny", "paper" }) {
        loop lp(modulation::QAM256, "pusch2", pusch_coding::NR_LDPC);
        lp.cfg.num = numerology::preset(preset);
        const transport_block_codec codec(lp.cfg);
        std::vector<std::uint8_t> payload(codec.payload_bytes());
        for (std::size_t i = 0; i < payload.size(); i++)
            payload[i] = static_cast<std::uint8_t>(i * 29 + 3);
        std::vector<std::uint8_t> got_simd, got_generic;
        const auto a = lp.run(1, payload, 1.5e-3, 0.01, &got_simd);
        const auto eq_simd = lp.eq;
        lp.simd = false;
        const auto b = lp.run(1, payload, 1.5e-3, 0.01, &got_generic);
        ASSERT_EQ(eq_simd.size(), lp.eq.size()) << preset;
        EXPECT_EQ(std::memcmp(eq_simd.data(), lp.eq.data(), eq_simd.size() * sizeof(gr_complex)), 0)
            << preset;
        EXPECT_TRUE(a.tb.header_ok) << preset;
        EXPECT_EQ(got_simd, payload) << preset;
        EXPECT_EQ(got_generic, got_simd) << preset;
        EXPECT_EQ(a.tb.mean_iterations, b.tb.mean_iterations) << preset;
        EXPECT_EQ(a.snr_db, b.snr_db) << preset;
        EXPECT_EQ(a.evm_db, b.evm_db) << preset;
    }
}

TEST(pusch_rx, bad_parameters)
{
    loop lp(modulation::QAM16, "pusch2");
    auto c = lp.cfg;
    c.dmrs = dmrs_config();
    EXPECT_THROW(pusch_rx{ c }, std::invalid_argument);
    c = lp.cfg;
    c.mod = modulation::PSK8;
    EXPECT_THROW(pusch_rx{ c }, std::invalid_argument);
    c = lp.cfg;
    c.freq_window = 2;
    EXPECT_THROW(pusch_rx{ c }, std::invalid_argument);
}

TEST(pusch_rx, garbage_slot_is_a_clean_failure)
{
    // Huge, infinite and NaN samples (the block zeroes non-finite ones first; the kernel must
    // still not misbehave): every case is a CRC failure with an empty payload.
    pusch_config cfg;
    cfg.num = numerology::preset("tiny");
    pusch_rx rx(cfg);
    const float vals[] = { 3e38f, -3e38f, std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN(), 1e-38f, 0.0f };
    for (float v : vals) {
        std::vector<gr_complex> y(14 * 64, gr_complex(v, -v));
        const auto r = rx.process(y.data(), 0);
        EXPECT_FALSE(r.tb.header_ok);
        EXPECT_TRUE(r.tb.sdu.data.empty());
    }
}
