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
#include <random>
#include <stdexcept>

using namespace gr::nrsar;
using namespace gr::nrsar::kernel;

namespace {
const char* alist_small = "/usr/share/gnuradio/fec/ldpc/n_0300_k_0152_gap_03.alist";

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

TEST(transport_block, crc24a_check_value)
{
    // CRC-24/LTE-A catalogue check value of "123456789" is 0xCDE703.
    const char* s = "123456789";
    EXPECT_EQ(crc24a_ref(reinterpret_cast<const std::uint8_t*>(s), 9), 0xCDE703u);
    // The codec appends exactly this CRC: check it on an unscrambled uncoded TB.
    transport_block_codec codec(8 * (5 + 9 + 3), "", 0);
    ASSERT_EQ(codec.payload_bytes(), 9u);
    std::vector<std::uint8_t> bits(codec.slot_bits());
    codec.encode(tb_header{}, reinterpret_cast<const std::uint8_t*>(s), 9, 0, bits.data());
    const auto c = gold_ref(0x2545F491u, bits.size()); // c_init of id 0, slot 0 (below)
    std::vector<std::uint8_t> bytes(17, 0);
    for (std::size_t i = 0; i < bits.size(); i++)
        bytes[i / 8] |= static_cast<std::uint8_t>((bits[i] ^ c[i]) << (7 - i % 8));
    EXPECT_EQ(bytes[0], 0);
    EXPECT_EQ(bytes[1], 9);
    EXPECT_EQ(std::memcmp(bytes.data() + 5, s, 9), 0);
    const std::uint32_t crc = crc24a_ref(bytes.data(), 14);
    EXPECT_EQ((std::uint32_t{ bytes[14] } << 16) | (bytes[15] << 8) | bytes[16], crc);
}

TEST(transport_block, sizes)
{
    transport_block_codec u(1000, "", 3);
    EXPECT_EQ(u.payload_bytes(), (1000u - 24u) / 8u - 5u);
    EXPECT_DOUBLE_EQ(u.code_rate(), 1.0);
    transport_block_codec l(1000, alist_small, 3);
    EXPECT_EQ(l.code_n(), 300u);
    EXPECT_EQ(l.code_k(), 152u);
    EXPECT_EQ(l.codewords(), 3u);
    EXPECT_EQ(l.payload_bytes(), (3u * 152u - 24u) / 8u - 5u);
}

TEST(transport_block, roundtrip_uncoded_and_ldpc)
{
    std::mt19937 rng(5);
    for (const char* alist : { "", alist_small }) {
        transport_block_codec codec(2000, alist, 77);
        std::vector<std::uint8_t> bits(codec.slot_bits());
        for (std::size_t len : { std::size_t{ 0 }, std::size_t{ 1 }, codec.payload_bytes() }) {
            std::vector<std::uint8_t> payload(len);
            for (auto& b : payload)
                b = static_cast<std::uint8_t>(rng());
            tb_header h;
            h.seq = 4242;
            h.flags = len ? tb_header::pdu_start : tb_header::filler;
            const std::uint64_t slot = 123456;
            codec.encode(h, payload.data(), len, slot, bits.data());
            const auto r = codec.decode(bits_to_llr(bits).data(), slot);
            EXPECT_TRUE(r.crc_ok) << alist;
            EXPECT_TRUE(r.header_ok);
            EXPECT_EQ(r.header.seq, 4242);
            EXPECT_EQ(r.header.payload_len, len);
            EXPECT_EQ(r.payload, payload);
            // wrong slot = wrong descrambling: CRC fails
            EXPECT_FALSE(codec.decode(bits_to_llr(bits).data(), slot + 1).crc_ok);
        }
    }
}

TEST(transport_block, scrambling_c_init)
{
    // The documented c_init = ((2^15 scrambling_id + (slot mod 2^15)) a + b) mod 2^31,
    // a = 0x9E3779B1 = 2654435761, b = 0x2545F491 = 625341585, worked out by hand:
    //  id 0, slot 0: v = 0, c_init = b = 0x2545F491.
    EXPECT_EQ(transport_block_codec::scrambling_c_init(0, 0), 0x2545F491u);
    //  id 3, slot 70000: 70000 mod 32768 = 4464, v = 3 * 32768 + 4464 = 102768,
    //  v a = 272791054286448 = 127028 * 2^31 + 501448304, 501448304 + 625341585 = 1126789889
    //  (< 2^31) = 0x43297301.
    EXPECT_EQ(transport_block_codec::scrambling_c_init(3, 70000), 0x43297301u);
    //  id 65535, slot 65535: v = 65535 * 2^15 + 32767 = 2^31 - 1 = -1 mod 2^31, so
    //  v a = -(a mod 2^31) = 2^31 - 506952113 = 1640531535; + b = 2265873120 - 2^31 =
    //  118389472 = 0x070E7AE0.
    EXPECT_EQ(transport_block_codec::scrambling_c_init(65535, 65535), 0x070E7AE0u);
    // The pre-image is TS 38.211 6.3.1.1's PUSCH form c_init = n_RNTI 2^15 + n_ID (PUSCH has
    // no codeword term q 2^14; that is PDSCH's 7.3.1.1) with n_RNTI = scrambling_id and
    // n_ID = slot mod 2^15: undo the affine map with a^-1 mod 2^31 = 0x0E8B2F51.
    const std::uint64_t a = 0x9E3779B1u, a_inv = 0x0E8B2F51u, b = 0x2545F491u, m = 1ull << 31;
    ASSERT_EQ(a * a_inv % m, 1u);
    for (unsigned id : { 0u, 1u, 7u, 1234u, 65535u })
        for (std::uint64_t slot : { 0ull, 1ull, 2ull, 32767ull, 32768ull, 123456ull }) {
            const std::uint64_t c = transport_block_codec::scrambling_c_init(id, slot);
            EXPECT_EQ((c + m - b) % m * a_inv % m, std::uint64_t{ id } * 32768 + slot % 32768)
                << "id " << id << " slot " << slot;
        }
}

TEST(transport_block, scrambled_bits_are_tb_xor_gold_sequence)
{
    // Uncoded G = 6000: the codec's output must be the TB (header | zero payload | CRC24A,
    // built here) xor c(i) of the bit-by-bit 38.211 5.2.1 Gold sequence with the hand c_init
    // 0x43297301 (id 3, slot 70000, above), and c(i) alone over the zero padding.
    transport_block_codec codec(6000, "", 3);
    tb_header h;
    h.seq = 0x1234;
    h.flags = tb_header::filler;
    std::vector<std::uint8_t> out(codec.slot_bits());
    codec.encode(h, nullptr, 0, 70000, out.data());
    std::vector<std::uint8_t> tb(codec.tb_bits() / 8, 0);
    tb[2] = 0x12;
    tb[3] = 0x34;
    tb[4] = tb_header::filler;
    const std::uint32_t crc = crc24a_ref(tb.data(), tb.size() - 3);
    tb[tb.size() - 3] = static_cast<std::uint8_t>(crc >> 16);
    tb[tb.size() - 2] = static_cast<std::uint8_t>(crc >> 8);
    tb[tb.size() - 1] = static_cast<std::uint8_t>(crc);
    const auto c = gold_ref(0x43297301u, out.size());
    int wrong = 0;
    for (std::size_t i = 0; i < out.size(); i++) {
        const int bit = i < 8 * tb.size() ? (tb[i / 8] >> (7 - i % 8)) & 1 : 0;
        wrong += out[i] != (bit ^ c[i]);
    }
    EXPECT_EQ(wrong, 0);
}

TEST(transport_block, zero_payload_looks_random)
{
    // 38.211 6.3.1.1: scrambled bits of an all-zero filler TB are balanced and differ per slot.
    transport_block_codec codec(6000, "", 0);
    std::vector<std::uint8_t> a(6000), b(6000);
    codec.encode(tb_header{}, nullptr, 0, 0, a.data());
    codec.encode(tb_header{}, nullptr, 0, 1, b.data());
    int ones = 0, diff = 0;
    for (int i = 0; i < 6000; i++) {
        ones += a[i];
        diff += a[i] != b[i];
    }
    EXPECT_NEAR(ones, 3000, 250);
    EXPECT_NEAR(diff, 3000, 250);
}

TEST(transport_block, ldpc_corrects_errors)
{
    transport_block_codec codec(2000, alist_small, 1);
    std::vector<std::uint8_t> bits(codec.slot_bits());
    std::vector<std::uint8_t> payload(codec.payload_bytes(), 0x5a);
    codec.encode(tb_header{}, payload.data(), payload.size(), 9, bits.data());
    // BPSK over AWGN, sigma = 0.45: raw bit error rate Q(1/0.45) = 1.3 %, LLR = 2 y / sigma^2
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.0f, 0.45f);
    std::vector<float> llr(bits.size());
    int raw_errors = 0;
    for (std::size_t i = 0; i < bits.size(); i++) {
        const float y = (bits[i] ? -1.0f : 1.0f) + g(rng);
        llr[i] = 2.0f * y / (0.45f * 0.45f);
        raw_errors += (y < 0) != (bits[i] != 0);
    }
    EXPECT_GT(raw_errors, 5); // hard decisions alone would fail the CRC
    const auto r = codec.decode(llr.data(), 9);
    EXPECT_TRUE(r.crc_ok);
    EXPECT_EQ(r.payload, payload);
}

TEST(transport_block, header_rules_and_garbage)
{
    tb_header h;
    std::uint8_t raw[5] = { 0, 10, 0, 1, tb_header::filler };
    EXPECT_FALSE(h.read(raw, 100)); // filler with payload
    raw[4] = 0x80;
    EXPECT_FALSE(h.read(raw, 100)); // unknown flag
    raw[4] = 0;
    EXPECT_FALSE(h.read(raw, 9)); // longer than the capacity
    EXPECT_TRUE(h.read(raw, 10));
    transport_block_codec codec(500, "", 0);
    std::vector<float> llr(500, std::nanf(""));
    EXPECT_FALSE(codec.decode(llr.data(), 0).header_ok);
}

TEST(transport_block, bad_parameters)
{
    EXPECT_THROW(transport_block_codec(1000, "/nonexistent.alist"), std::invalid_argument);
    EXPECT_THROW(transport_block_codec(200, alist_small), std::invalid_argument);
    EXPECT_THROW(transport_block_codec(64, ""), std::invalid_argument);
    EXPECT_THROW(transport_block_codec(1000, "", 65536), std::invalid_argument);
}
