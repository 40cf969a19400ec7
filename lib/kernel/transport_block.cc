/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/digital/crc.h>
#include <gnuradio/fec/generic_decoder.h>
#include <gnuradio/fec/generic_encoder.h>
#include <gnuradio/fec/ldpc_decoder.h>
#include <gnuradio/fec/ldpc_encoder.h>
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {
// CRC24A of TS 38.212 5.1: MSB-first polynomial 0x864CFB, zero initial value, no final xor.
constexpr std::uint64_t crc24a_poly = 0x864CFBu;
// awgn_bp takes BPSK samples y (bit 0 -> -1, bit 1 -> +1) with noise sigma and forms the
// likelihood from 2 y / sigma^2: an LLR L (positive = bit 0) is the sample y = -L sigma^2 / 2.
constexpr float bp_sigma = 0.5f;
constexpr float llr_clip = 40.0f; // keeps exp() inside awgn_bp finite
} // namespace

std::size_t pusch_slot_bits(const numerology& num, modulation mod, const dmrs_config& dmrs)
{
    const std::size_t data_symbols = num.symbols_per_slot - dmrs.symbols.size();
    return data_symbols * num.num_subcarriers * constellation::bits_per_symbol(mod);
}

void tb_header::write(std::uint8_t* out) const
{
    out[0] = static_cast<std::uint8_t>(payload_len >> 8);
    out[1] = static_cast<std::uint8_t>(payload_len & 0xff);
    out[2] = static_cast<std::uint8_t>(seq >> 8);
    out[3] = static_cast<std::uint8_t>(seq & 0xff);
    out[4] = flags;
}

bool tb_header::read(const std::uint8_t* in, std::size_t capacity)
{
    payload_len = static_cast<std::uint16_t>((in[0] << 8) | in[1]);
    seq = static_cast<std::uint16_t>((in[2] << 8) | in[3]);
    flags = in[4];
    if (payload_len > capacity || (flags & ~known_flags) != 0)
        return false;
    if ((flags & filler) && payload_len != 0)
        return false;
    return true;
}

transport_block_codec::transport_block_codec(std::size_t slot_bits,
                                             const std::string& ldpc_alist,
                                             unsigned scrambling_id,
                                             unsigned max_iterations)
    : d_G(slot_bits),
      d_scrambling_id(scrambling_id),
      d_crc(std::make_unique<gr::digital::crc>(24, crc24a_poly, 0, 0, false, false))
{
    check_range("scrambling_id", scrambling_id, 0u, 65535u);
    check_at_least("max_iterations", max_iterations, 1u);
    std::size_t info = d_G;
    if (!ldpc_alist.empty()) {
        if (!std::ifstream(ldpc_alist).good())
            throw_param("ldpc_alist", ldpc_alist, "is not a readable alist file");
        d_enc = gr::fec::ldpc_encoder::make(ldpc_alist);
        d_dec = gr::fec::ldpc_decoder::make(
            ldpc_alist, bp_sigma, static_cast<int>(max_iterations));
        d_n = static_cast<unsigned>(d_enc->get_output_size());
        d_k = static_cast<unsigned>(d_enc->get_input_size());
        if (d_n == 0 || d_k == 0 || d_k >= d_n)
            throw_param("ldpc_alist", ldpc_alist, "does not describe a code with 0 < k < n");
        d_C = static_cast<unsigned>(d_G / d_n);
        if (d_C == 0)
            throw_param("slot bits",
                        d_G,
                        "must hold one LDPC codeword of n = " + std::to_string(d_n) + " bits");
        info = static_cast<std::size_t>(d_C) * d_k;
    }
    const std::size_t overhead = 8 * (tb_header::bytes + 3);
    if (info < overhead + 8)
        throw_param("slot bits", d_G, "leave no payload byte after header and CRC24A");
    d_payload = (info - 24) / 8 - tb_header::bytes;
    d_payload = std::min<std::size_t>(d_payload, 65535); // payload_len is 16 bits
    d_soft.resize(d_n);
    d_bits.resize(std::max<std::size_t>(info, tb_bits()));
    d_bytes.resize(tb_bits() / 8);
}

transport_block_codec::~transport_block_codec() = default;
transport_block_codec::transport_block_codec(transport_block_codec&&) noexcept = default;
transport_block_codec&
transport_block_codec::operator=(transport_block_codec&&) noexcept = default;

double transport_block_codec::code_rate() const
{
    return coded() ? static_cast<double>(d_k) / d_n : 1.0;
}

double transport_block_codec::efficiency() const
{
    return 8.0 * static_cast<double>(d_payload) / static_cast<double>(d_G);
}

std::uint32_t transport_block_codec::scrambling_c_init(unsigned scrambling_id, std::uint64_t slot)
{
    // 38.211's n_RNTI 2^15 + n_ID form, then an affine bijection of Z / 2^31 (odd multiplier):
    // low-weight c_init (0, 1, 2, ...) leave c(n) visibly biased for thousands of bits after
    // Nc = 1600 (c_init = 0: 39 % ones over the first 3072 bits), which would put a mean
    // (a zero-Doppler line) into the radar grid of filler slots.
    const std::uint64_t v = (std::uint64_t{ scrambling_id } << 15) + (slot & 0x7fffu);
    return static_cast<std::uint32_t>((v * 0x9E3779B1u + 0x2545F491u) & 0x7fffffffu);
}

void transport_block_codec::encode(tb_header header,
                                   const std::uint8_t* payload,
                                   std::size_t len,
                                   std::uint64_t slot,
                                   std::uint8_t* out) const
{
    len = std::min(len, d_payload);
    header.payload_len = static_cast<std::uint16_t>(len);
    std::vector<std::uint8_t> tb(tb_bits() / 8, 0);
    header.write(tb.data());
    if (len > 0)
        std::memcpy(tb.data() + tb_header::bytes, payload, len);
    const std::size_t crc_at = tb.size() - 3;
    const std::uint64_t crc = d_crc->compute(tb.data(), crc_at);
    tb[crc_at] = static_cast<std::uint8_t>(crc >> 16);
    tb[crc_at + 1] = static_cast<std::uint8_t>(crc >> 8);
    tb[crc_at + 2] = static_cast<std::uint8_t>(crc);

    std::fill(out, out + d_G, 0);
    if (!coded()) {
        for (std::size_t i = 0; i < tb_bits(); i++)
            out[i] = (tb[i / 8] >> (7 - i % 8)) & 1u;
    } else {
        std::vector<std::uint8_t> info(static_cast<std::size_t>(d_C) * d_k, 0);
        for (std::size_t i = 0; i < tb_bits(); i++)
            info[i] = (tb[i / 8] >> (7 - i % 8)) & 1u;
        for (unsigned c = 0; c < d_C; c++)
            d_enc->generic_work(info.data() + static_cast<std::size_t>(c) * d_k,
                                out + static_cast<std::size_t>(c) * d_n);
    }
    // 38.211 6.3.1.1 scrambling over all G bits (padding included).
    gold_sequence prbs(scrambling_c_init(d_scrambling_id, slot));
    std::size_t i = 0;
    for (; i + 32 <= d_G; i += 32) {
        const std::uint32_t w = prbs.next_word();
        for (unsigned b = 0; b < 32; b++)
            out[i + b] ^= static_cast<std::uint8_t>((w >> b) & 1u);
    }
    if (i < d_G) {
        const auto rest = static_cast<unsigned>(d_G - i);
        const std::uint32_t w = prbs.next_bits(rest);
        for (unsigned b = 0; b < rest; b++)
            out[i + b] ^= static_cast<std::uint8_t>((w >> b) & 1u);
    }
}

tb_result transport_block_codec::parse(const std::uint8_t* tb) const
{
    tb_result r;
    const std::size_t crc_at = tb_bits() / 8 - 3;
    const std::uint64_t crc = d_crc->compute(tb, crc_at);
    const std::uint64_t got = (std::uint64_t{ tb[crc_at] } << 16) |
                              (std::uint64_t{ tb[crc_at + 1] } << 8) | tb[crc_at + 2];
    r.crc_ok = crc == got;
    const bool header_ok = r.header.read(tb, d_payload);
    r.header_ok = r.crc_ok && header_ok;
    if (r.header_ok)
        r.payload.assign(tb + tb_header::bytes, tb + tb_header::bytes + r.header.payload_len);
    return r;
}

tb_result transport_block_codec::decode(const float* llr, std::uint64_t slot)
{
    // Descrambling = sign flip of the LLR where c(i) = 1; only the info part is needed.
    const std::size_t used = coded() ? static_cast<std::size_t>(d_C) * d_n : tb_bits();
    gold_sequence prbs(scrambling_c_init(d_scrambling_id, slot));
    auto clean = [](float v) { return std::isfinite(v) ? v : 0.0f; };
    if (!coded()) {
        for (std::size_t i = 0; i < used; i++) {
            const float v = clean(llr[i]);
            const bool c = prbs.next_bits(1) != 0;
            // hard decision: bit = (v < 0) xor c; ties (0) decide 0 before descrambling
            d_bits[i] = static_cast<std::uint8_t>((v < 0.0f) != c);
        }
    } else {
        const float scale = -bp_sigma * bp_sigma / 2.0f;
        for (unsigned cw = 0; cw < d_C; cw++) {
            for (unsigned i = 0; i < d_n; i++) {
                float v = clean(llr[static_cast<std::size_t>(cw) * d_n + i]);
                if (prbs.next_bits(1))
                    v = -v;
                v = std::max(-llr_clip, std::min(llr_clip, v));
                d_soft[i] = v * scale;
            }
            d_dec->generic_work(d_soft.data(),
                                d_bits.data() + static_cast<std::size_t>(cw) * d_k);
        }
    }
    std::fill(d_bytes.begin(), d_bytes.end(), 0);
    for (std::size_t i = 0; i < tb_bits(); i++)
        d_bytes[i / 8] |= static_cast<std::uint8_t>((d_bits[i] & 1u) << (7 - i % 8));
    return parse(d_bytes.data());
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
