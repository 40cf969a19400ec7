/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <stdexcept>

using namespace gr::nrsar;
using namespace gr::nrsar::kernel;

namespace {

// Bit-by-bit TS 38.211 5.2.1 Gold sequence, independent of gold_sequence.
std::vector<int> gold_ref(std::uint32_t c_init, std::size_t n)
{
    const std::size_t Nc = 1600, len = n + Nc + 31;
    std::vector<int> x1(len, 0), x2(len, 0);
    x1[0] = 1;
    for (int i = 0; i < 31; i++)
        x2[i] = (c_init >> i) & 1;
    for (std::size_t i = 0; i + 31 < len; i++) {
        x1[i + 31] = (x1[i + 3] + x1[i]) % 2;
        x2[i + 31] = (x2[i + 3] + x2[i + 2] + x2[i + 1] + x2[i]) % 2;
    }
    std::vector<int> c(n);
    for (std::size_t i = 0; i < n; i++)
        c[i] = (x1[i + Nc] + x2[i + Nc]) % 2;
    return c;
}

// CRC24A by polynomial long division over the bits (TS 38.212 5.1).
std::uint32_t crc24a_ref(const std::uint8_t* data, std::size_t len)
{
    std::uint32_t reg = 0;
    for (std::size_t i = 0; i < 8 * len; i++) {
        const std::uint32_t bit = (data[i / 8] >> (7 - i % 8)) & 1u;
        const std::uint32_t top = (reg >> 23) & 1u;
        reg = ((reg << 1) & 0xffffffu);
        if (top ^ bit)
            reg ^= 0x864cfbu;
    }
    return reg;
}

std::vector<float> bits_to_llr(const std::vector<std::uint8_t>& bits, float mag = 10.0f)
{
    std::vector<float> llr(bits.size());
    for (std::size_t i = 0; i < bits.size(); i++)
        llr[i] = bits[i] ? -mag : mag;
    return llr;
}
} // namespace

TEST(dmrs, values_match_bitwise_gold)
{
    for (unsigned nid : { 0u, 1u, 511u, 65535u })
        for (unsigned slot : { 0u, 7u, 19u })
            for (unsigned l : { 2u, 11u }) {
                const std::uint64_t cinit =
                    ((1ull << 17) * (14ull * slot + l + 1) * (2ull * nid + 1) + 2ull * nid) %
                    (1ull << 31);
                EXPECT_EQ(dmrs_c_init(nid, slot, l), cinit);
                const auto r = dmrs_values(nid, slot, l, 40);
                const auto c = gold_ref(static_cast<std::uint32_t>(cinit), 80);
                for (int i = 0; i < 40; i++) {
                    EXPECT_FLOAT_EQ(r[i].real(), (1 - 2 * c[2 * i]) / std::sqrt(2.0));
                    EXPECT_FLOAT_EQ(r[i].imag(), (1 - 2 * c[2 * i + 1]) / std::sqrt(2.0));
                }
            }
}


namespace {
pusch_config tiny_cfg(pusch_coding coding, modulation mod = modulation::QAM256, unsigned mcs = 27)
{
    pusch_config c;
    c.num = numerology::preset("tiny");
    c.mod = mod;
    c.coding = coding;
    c.mcs = mcs;
    return c;
}

std::vector<std::uint8_t> mac_pdu(const std::vector<std::uint8_t>& data, std::size_t tb_bytes)
{
    mac_sdu s;
    s.filler = false;
    s.data = data;
    std::vector<std::uint8_t> tb(tb_bytes);
    s.write(tb.data(), tb.size());
    return tb;
}
} // namespace

// The bytes of 38.321 6.1.2 / 38.322 6.2.2.3 written by hand.
TEST(mac_sdu, layout_of_the_standard_headers)
{
    mac_sdu s;
    s.filler = false;
    s.data = { 0xd0, 0xd1, 0xd2, 0xd3, 0xd4 };
    std::vector<std::uint8_t> tb(12, 0xee);
    s.write(tb.data(), tb.size());
    // R 0 F 1 LCID 4 = 0x44, L = 1 + 5, SI 00 R 000000, data, padding LCID 63, zeros
    EXPECT_EQ(tb, (std::vector<std::uint8_t>{ 0x44, 0x00, 0x06, 0x00, 0xd0, 0xd1, 0xd2, 0xd3,
                                              0xd4, 0x3f, 0x00, 0x00 }));
    s.si = mac_sdu::middle; // SI 11, SN 5, SO 0x1234
    s.sn = 5;
    s.so = 0x1234;
    s.data = { 0xaa };
    s.write(tb.data(), 7);
    EXPECT_EQ(std::vector<std::uint8_t>(tb.begin(), tb.begin() + 7),
              (std::vector<std::uint8_t>{ 0x44, 0x00, 0x04, 0xc5, 0x12, 0x34, 0xaa }));
    mac_sdu r;
    ASSERT_TRUE(r.read(tb.data(), 7));
    EXPECT_FALSE(r.filler);
    EXPECT_EQ(r.si, mac_sdu::middle);
    EXPECT_EQ(r.sn, 5);
    EXPECT_EQ(r.so, 0x1234);
    EXPECT_EQ(r.data, s.data);
    mac_sdu f; // filler: the padding subheader alone
    f.write(tb.data(), 12);
    EXPECT_EQ(tb[0], 0x3f);
    ASSERT_TRUE(r.read(tb.data(), 12));
    EXPECT_TRUE(r.filler);
    // capacity: TB bytes minus 3 (MAC) minus 1 or 3 (RLC)
    EXPECT_EQ(mac_sdu::capacity(12, mac_sdu::complete), 8u);
    EXPECT_EQ(mac_sdu::capacity(12, mac_sdu::last), 6u);
    EXPECT_EQ(mac_sdu::capacity(4, mac_sdu::complete), 0u);
}

TEST(mac_sdu, refuses_what_it_does_not_write)
{
    mac_sdu r;
    const std::vector<std::vector<std::uint8_t>> bad = {
        { 0x00, 0x00, 0x00, 0x00 },             // LCID 0 (all-zero TB)
        { 0xc4, 0x00, 0x02, 0x00, 0x01 },       // R bit set
        { 0x44, 0x00, 0x09, 0x00, 0x01 },       // L beyond the TB
        { 0x44, 0x00, 0x01, 0x00, 0x3f },       // no data byte
        { 0x44, 0x00, 0x02, 0x05, 0x01, 0x3f }, // complete SDU with R bits set
        { 0x44, 0x00, 0x02, 0x00, 0x01, 0x00 }, // no padding subheader after the SDU
        { 0x05, 0x02, 0x00, 0x01 },             // F = 0, another LCID
    };
    for (const auto& tb : bad)
        EXPECT_FALSE(r.read(tb.data(), tb.size())) << int(tb[0]) << " " << int(tb[2]);
}

TEST(transport_block, sizes)
{
    // uncoded: A = 8 floor((G - 24) / 8), G = 12 x 64 x 4 (16-QAM, pusch2)
    const transport_block_codec u(tiny_cfg(pusch_coding::NONE, modulation::QAM16));
    EXPECT_EQ(u.slot_bits(), 3072u);
    EXPECT_EQ(u.tbs_bits(), 3048u);
    EXPECT_EQ(u.payload_bytes(), 3048u / 8 - 4);
    EXPECT_FALSE(u.coded());
    // coded, qam256 table MCS 27 (Qm 8, R 948/1024) on 5 PRB x (168 - 24) REs:
    // N_info = 720 x 948/1024 x 8 = 5332.5 > 3824: n = floor(log2(5332.5 - 24)) - 5 = 7,
    // N'_info = max(3840, 2^7 round((5332.5 - 24) / 2^7)) = 5248; R > 1/4, N'_info <= 8424:
    // C = ceil((5248 + 24) / 8424) = 1, TBS = 8 ceil((5248 + 24) / 8) - 24 = 5248
    const transport_block_codec c(tiny_cfg(pusch_coding::NR_LDPC));
    EXPECT_EQ(c.slot_bits(), 6144u);
    EXPECT_EQ(c.tbs_bits(), 5248u);
    EXPECT_EQ(c.code_blocks(), 1u);
    EXPECT_EQ(c.base_graph(), 1); // A > 3824 and R > 0.67 (38.212 6.2.2)
    EXPECT_NEAR(c.code_rate(), (5248.0 + 24.0) / 6144.0, 1e-12);
}

TEST(transport_block, roundtrip_uncoded_and_coded)
{
    std::mt19937 rng(5);
    for (auto coding : { pusch_coding::NONE, pusch_coding::NR_LDPC }) {
        transport_block_codec codec(tiny_cfg(coding));
        for (std::size_t len : { std::size_t{ 1 }, std::size_t{ 37 }, codec.payload_bytes() }) {
            std::vector<std::uint8_t> data(len);
            for (auto& b : data)
                b = static_cast<std::uint8_t>(rng());
            auto tb = mac_pdu(data, codec.tb_bytes());
            std::vector<std::uint8_t> bits(codec.slot_bits());
            codec.encode(tb.data(), 0, 11, bits.data());
            const auto r = codec.decode(bits_to_llr(bits).data(), 0, 11, false);
            EXPECT_TRUE(r.crc_ok && r.parity_ok && r.header_ok) << len;
            EXPECT_EQ(r.sdu.data, data);
            EXPECT_EQ(r.sdu.si, mac_sdu::complete);
        }
    }
}

// 38.211 6.3.1.1: c_init = n_RNTI 2^15 + n_ID, the same every slot; uncoded, the G bits are
// the TB, its CRC24A and zeros, xor c(n).
TEST(transport_block, standard_scrambling_by_hand)
{
    auto cfg = tiny_cfg(pusch_coding::NONE, modulation::QPSK);
    cfg.n_rnti = 0x4601;
    cfg.n_id = 77;
    transport_block_codec codec(cfg);
    const std::uint32_t c_init = 0x4601u * 32768u + 77u; // 589,332,557
    EXPECT_EQ(codec.c_init(0), c_init);
    EXPECT_EQ(codec.c_init(123), c_init);
    const auto tb = mac_pdu({ 1, 2, 3 }, codec.tb_bytes());
    std::vector<std::uint8_t> bits(codec.slot_bits());
    codec.encode(tb.data(), 0, 5, bits.data());
    const auto c = gold_ref(c_init, bits.size());
    const std::uint32_t crc = crc24a_ref(tb.data(), tb.size());
    for (std::size_t i = 0; i < bits.size(); i++) {
        int b = 0;
        if (i < 8 * tb.size())
            b = (tb[i / 8] >> (7 - i % 8)) & 1;
        else if (i < 8 * tb.size() + 24)
            b = (crc >> (23 - (i - 8 * tb.size()))) & 1;
        ASSERT_EQ(bits[i], b ^ c[i]) << i;
    }
    // the module's option: a different sequence per slot
    cfg.scrambling = pusch_scrambling::PER_SLOT;
    transport_block_codec per_slot(cfg);
    EXPECT_EQ(per_slot.c_init(3), transport_block_codec::per_slot_c_init(77, 3));
    EXPECT_EQ(per_slot.c_init(3),
              static_cast<std::uint32_t>(((77ull * 32768 + 3) * 0x9E3779B1ull + 0x2545F491ull) %
                                         (1ull << 31)));
    EXPECT_NE(per_slot.c_init(3), per_slot.c_init(4));
}

TEST(transport_block, wrong_scrambling_or_noise_fails_cleanly)
{
    auto cfg = tiny_cfg(pusch_coding::NR_LDPC, modulation::QPSK, 4);
    transport_block_codec tx(cfg);
    cfg.n_rnti += 1;
    transport_block_codec other(cfg);
    const auto tb = mac_pdu({ 9, 8, 7 }, tx.tb_bytes());
    std::vector<std::uint8_t> bits(tx.slot_bits());
    tx.encode(tb.data(), 0, 0, bits.data());
    auto r = other.decode(bits_to_llr(bits).data(), 0, 0, false);
    EXPECT_FALSE(r.header_ok);
    EXPECT_TRUE(r.sdu.data.empty());
    // all-zero LLRs (nothing received) decode to zeros: CRC ok, but no MAC PDU
    std::vector<float> zero(tx.slot_bits(), 0.0f);
    r = tx.decode(zero.data(), 0, 0, false);
    EXPECT_FALSE(r.header_ok);
    std::vector<float> nan(tx.slot_bits(), std::nanf(""));
    r = tx.decode(nan.data(), 0, 0, false);
    EXPECT_FALSE(r.header_ok);
}

// HARQ: rv 0 and rv 2 each keep fewer bits than the K' = 1880 information bits of the block
// (60 % and 40 % of E = 3072: 1843 and 1228), so neither decodes alone; together they do.
TEST(transport_block, harq_combining_of_rv0_and_rv2)
{
    auto cfg = tiny_cfg(pusch_coding::NR_LDPC, modulation::QAM16, 10); // R 658/1024
    transport_block_codec codec(cfg);
    const auto tb = mac_pdu({ 0x5a, 0xa5, 0x0f }, codec.tb_bytes());
    std::vector<std::uint8_t> b0(codec.slot_bits()), b2(codec.slot_bits());
    codec.encode(tb.data(), 0, 0, b0.data());
    codec.encode(tb.data(), 2, 1, b2.data());
    auto l0 = bits_to_llr(b0);
    std::fill(l0.begin() + l0.size() * 6 / 10, l0.end(), 0.0f);
    EXPECT_FALSE(codec.decode(l0.data(), 0, 0, false).header_ok);
    auto l2 = bits_to_llr(b2);
    std::fill(l2.begin() + l2.size() * 4 / 10, l2.end(), 0.0f);
    EXPECT_FALSE(codec.decode(l2.data(), 2, 1, false).header_ok);
    codec.decode(l0.data(), 0, 0, false);
    const auto r = codec.decode(l2.data(), 2, 1, true);
    EXPECT_TRUE(r.header_ok);
    EXPECT_EQ(r.sdu.data, (std::vector<std::uint8_t>{ 0x5a, 0xa5, 0x0f }));
}

TEST(transport_block, bad_parameters)
{
    auto expect_refused = [](pusch_config c, const char* name) {
        try {
            transport_block_codec t(c);
            ADD_FAILURE() << name << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    // each case breaks one field of a valid configuration
    const std::vector<std::pair<std::function<void(pusch_config&)>, const char*>> cases = {
        { [](pusch_config& c) { c.mcs = 28; }, "mcs = 28 must be in [0, 27]" }, // reserved rows
        { [](pusch_config& c) { c.mcs = 10; }, // a 16-QAM row with 256-QAM
          "mcs = 10 of mcs_table qam256 has Qm = 4 but mod has 8" },
        { [](pusch_config& c) { c.mcs_table = "qam1024"; }, "mcs_table" },
        { [](pusch_config& c) { c.rv = 4; }, "rv = 4" },
        { [](pusch_config& c) { c.repetitions = 3; }, "repetitions = 3" },
        { [](pusch_config& c) { c.coding = pusch_coding::NONE; c.repetitions = 2; },
          "repetitions = 2 needs coding NR_LDPC" },
        { [](pusch_config& c) { c.n_id = 1024; }, "n_id = 1024" },
        { [](pusch_config& c) { c.n_rnti = 65536; }, "n_rnti = 65536" },
        { [](pusch_config& c) { c.mod = modulation::PSK8; }, "mod" },
        { [](pusch_config& c) { c.first_slot = (std::uint64_t{ 1 } << 40) + 1; },
          "first_slot = 1099511627777 must be at most 2^40" },
    };
    for (const auto& [breaks, message] : cases) {
        auto c = tiny_cfg(pusch_coding::NR_LDPC);
        breaks(c);
        expect_refused(c, message);
    }
    auto c = tiny_cfg(pusch_coding::NR_LDPC, modulation::QAM64, 28); // qam64 table
    c.mcs_table = "qam64";
    c.dmrs = dmrs_config::preset("pusch1");
    // 64-QAM R 948/1024, one DMRS symbol: TBS 4352, (4352 + 24) / 4992 = 0.88 (< 0.95)
    EXPECT_NO_THROW(transport_block_codec{ c });
}
