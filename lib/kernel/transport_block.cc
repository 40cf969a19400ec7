/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "bit_pack.h"
#include "param_check.h"
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_tbs.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gr {
namespace nrsar {

namespace {
// rv_id of the n-th transmission occasion, TS 38.214 Table 6.1.2.1-2: the cycle 0, 2, 3, 1
// entered at the rv the DCI indicates.
constexpr unsigned rv_cycle[4] = { 0, 2, 3, 1 };
// 38.214 5.1.3.2 leaves decoding to the UE above an effective rate of 0.95.
constexpr double max_effective_rate = 0.95;
} // namespace

unsigned pusch_config::rv_of(unsigned pos) const
{
    unsigned i = 0;
    while (rv_cycle[i] != rv % 4)
        i++;
    return rv_cycle[(i + pos) % 4];
}

void pusch_config::validate() const
{
    num.validate();
    dmrs.validate(num);
    if (!kernel::soft_demapper::supported(mod))
        throw_param("mod",
                    static_cast<int>(mod),
                    "is not decodable by pusch_receiver (QPSK, QAM16, QAM64, QAM256 only)");
    check_range("rv", rv, 0u, 3u);
    if (repetitions != 1 && repetitions != 2 && repetitions != 4 && repetitions != 8)
        throw_param("repetitions", repetitions, "must be 1, 2, 4 or 8 (pusch-AggregationFactor)");
    if (repetitions > 1 && coding != pusch_coding::NR_LDPC)
        throw_param("repetitions", repetitions, "needs coding NR_LDPC (soft combining)");
    check_range("n_rnti", n_rnti, 0u, 65535u);
    check_range("n_id", n_id, 0u, 1023u);
    if (freq_window < 1 || freq_window % 2 == 0)
        throw_param("freq_window", freq_window, "must be odd and >= 1");
    check_at_least("max_iterations", max_iterations, 1u);
    check_at_least("max_queued_bytes", max_queued_bytes, std::uint64_t{ 1 });
    if (first_slot > (std::uint64_t{ 1 } << 40))
        throw_param("first_slot", first_slot, "must be at most 2^40");
    if (coding == pusch_coding::NR_LDPC) {
        const auto e = kernel::nr_mcs(kernel::nr_parse_mcs_table(mcs_table), mcs);
        const unsigned qm = kernel::constellation::bits_per_symbol(mod);
        if (e.qm != qm)
            throw_param("mcs",
                        mcs,
                        "of mcs_table " + mcs_table + " has Qm = " + std::to_string(e.qm) +
                            " but mod has " + std::to_string(qm) + " bits per symbol");
        if (num.num_subcarriers < 12)
            throw_param("num_subcarriers", num.num_subcarriers, "must hold one PRB (12) for NR_LDPC");
    }
}

namespace kernel {

std::size_t pusch_slot_bits(const numerology& num, modulation mod, const dmrs_config& dmrs)
{
    const std::size_t data_symbols = num.symbols_per_slot - dmrs.symbols.size();
    return data_symbols * num.num_subcarriers * constellation::bits_per_symbol(mod);
}

std::size_t mac_sdu::capacity(std::size_t tb_bytes, segment_info si)
{
    const std::size_t header = mac_header_bytes + rlc_header_bytes(si);
    if (tb_bytes <= header)
        return 0;
    // L (16 bits) counts the RLC header and the data
    return std::min(tb_bytes - header, std::size_t{ 65535 } - rlc_header_bytes(si));
}

void mac_sdu::write(std::uint8_t* tb, std::size_t tb_bytes) const
{
    std::memset(tb, 0, tb_bytes);
    if (filler) {
        tb[0] = lcid_padding;
        return;
    }
    const std::size_t rlc = rlc_header_bytes(si);
    const std::size_t L = rlc + data.size();
    tb[0] = 0x40 | lcid; // R = 0, F = 1 (16-bit L)
    tb[1] = static_cast<std::uint8_t>(L >> 8);
    tb[2] = static_cast<std::uint8_t>(L);
    tb[3] = static_cast<std::uint8_t>((si << 6) | (si == complete ? 0 : (sn & 0x3f)));
    if (rlc == 3) {
        tb[4] = static_cast<std::uint8_t>(so >> 8);
        tb[5] = static_cast<std::uint8_t>(so);
    }
    std::copy(data.begin(), data.end(), tb + mac_header_bytes + rlc);
    const std::size_t end = mac_header_bytes + L;
    if (end < tb_bytes)
        tb[end] = lcid_padding;
}

bool mac_sdu::read(const std::uint8_t* tb, std::size_t tb_bytes)
{
    data.clear();
    if (tb_bytes == 0 || (tb[0] & 0x80))
        return false;
    const std::uint8_t id = tb[0] & 0x3f;
    if (id == lcid_padding) {
        filler = true;
        return true;
    }
    if (id != lcid || !(tb[0] & 0x40) || tb_bytes < mac_header_bytes + 2)
        return false;
    filler = false;
    const std::size_t L = (std::size_t{ tb[1] } << 8) | tb[2];
    if (mac_header_bytes + L > tb_bytes)
        return false;
    si = static_cast<segment_info>(tb[3] >> 6);
    const std::size_t rlc = rlc_header_bytes(si);
    if (L <= rlc)
        return false;
    sn = si == complete ? 0 : (tb[3] & 0x3f);
    if (si == complete && (tb[3] & 0x3f))
        return false;
    so = rlc == 3 ? static_cast<std::uint16_t>((tb[4] << 8) | tb[5]) : 0;
    const std::size_t end = mac_header_bytes + L;
    if (end < tb_bytes && tb[end] != lcid_padding)
        return false;
    data.assign(tb + mac_header_bytes + rlc, tb + end);
    return true;
}

namespace {
std::size_t tbs_of(const pusch_config& cfg, std::size_t g)
{
    cfg.validate();
    if (cfg.coding == pusch_coding::NONE)
        return 8 * ((g - std::min<std::size_t>(g, 24)) / 8);
    // 38.214 5.1.3.2 on the grid: N'_RE = 12 N_symb - N_DMRS^PRB, N_RE = min(156, N'_RE)
    // n_PRB, N_info = N_RE R Qm (one layer). n_PRB = floor(N / 12) may exceed the 275 of
    // 38.101 (paper: 277); the formula is applied as written.
    const auto e = nr_mcs(nr_parse_mcs_table(cfg.mcs_table), cfg.mcs);
    const unsigned n_prb = cfg.num.num_subcarriers / 12;
    const unsigned n_re_prb =
        12 * cfg.num.symbols_per_slot - 12 * static_cast<unsigned>(cfg.dmrs.symbols.size());
    const double n_info = double(std::min(156u, n_re_prb)) * n_prb * e.code_rate() * e.qm;
    return nr_tbs_from_n_info(n_info, e.code_rate());
}
} // namespace

transport_block_codec::transport_block_codec(const pusch_config& cfg)
    : d_cfg(cfg),
      d_G(pusch_slot_bits(cfg.num, cfg.mod, cfg.dmrs)),
      d_A(tbs_of(cfg, d_G)),
      d_crc(nr_crc_type::crc24a)
{
    if (mac_sdu::capacity(tb_bytes(), mac_sdu::middle) == 0)
        throw_param("slot bits",
                    d_G,
                    "give a TBS of " + std::to_string(d_A) +
                        " bits: no payload byte after the MAC and RLC headers (larger mcs or grid)");
    if (cfg.coding == pusch_coding::NR_LDPC) {
        const double r = double(d_A + nr_tb_crc_length(d_A)) / double(d_G);
        if (r > max_effective_rate)
            throw_param("mcs",
                        cfg.mcs,
                        "gives an effective code rate " + std::to_string(r) +
                            " above 0.95 on this grid (38.214 5.1.3.2): choose a lower mcs");
        const auto e = nr_mcs(nr_parse_mcs_table(cfg.mcs_table), cfg.mcs);
        d_ulsch = std::make_unique<nr_ulsch>(
            d_A, e.code_rate(), e.qm, d_G, 1, 0, cfg.max_iterations);
    }
    d_bits.resize(d_A + 24);
}

transport_block_codec::~transport_block_codec() = default;
transport_block_codec::transport_block_codec(transport_block_codec&&) noexcept = default;
transport_block_codec&
transport_block_codec::operator=(transport_block_codec&&) noexcept = default;

double transport_block_codec::code_rate() const
{
    const std::size_t crc = coded() ? nr_tb_crc_length(d_A) : 24;
    return double(d_A + crc) / double(d_G);
}

double transport_block_codec::efficiency() const
{
    return 8.0 * static_cast<double>(payload_bytes()) / static_cast<double>(d_G);
}

std::uint32_t transport_block_codec::per_slot_c_init(unsigned n_id, std::uint64_t slot)
{
    // 38.211's n_RNTI 2^15 + n_ID form with the slot in n_ID's place, then an affine bijection
    // of Z / 2^31 (odd multiplier): low-weight c_init (0, 1, 2, ...) leave c(n) visibly biased
    // for thousands of bits after Nc = 1600 (c_init = 0: 39 % ones over the first 3072 bits).
    const std::uint64_t v = (std::uint64_t{ n_id } << 15) + (slot & 0x7fffu);
    return static_cast<std::uint32_t>((v * 0x9E3779B1u + 0x2545F491u) & 0x7fffffffu);
}

std::uint32_t transport_block_codec::c_init(std::uint64_t slot) const
{
    return d_cfg.scrambling == pusch_scrambling::STANDARD
               ? nr_scrambling_c_init(d_cfg.n_rnti, d_cfg.n_id)
               : per_slot_c_init(d_cfg.n_id, slot);
}

void transport_block_codec::encode(const std::uint8_t* tb,
                                   unsigned rv,
                                   std::uint64_t slot,
                                   std::uint8_t* out)
{
    for (std::size_t i = 0; i < d_A; i++)
        d_bits[i] = (tb[i / 8] >> (7 - i % 8)) & 1u;
    if (coded()) {
        d_ulsch->encode(d_bits.data(), rv, c_init(slot), out);
        return;
    }
    d_crc.attach(d_bits.data(), d_A, out);
    std::fill(out + d_A + 24, out + d_G, 0);
    // 38.211 6.3.1.1 over all G bits (padding included)
    gold_sequence c(c_init(slot));
    std::vector<std::uint8_t> scr(d_G);
    c.generate_unpacked(scr.data(), d_G);
    for (std::size_t i = 0; i < d_G; i++)
        out[i] ^= scr[i];
}

void transport_block_codec::set_threads(unsigned threads)
{
    check_range("threads", threads, 1u, 2u);
    if (d_ulsch)
        d_ulsch->set_threads(threads);
}

tb_result transport_block_codec::decode(const float* llr,
                                        unsigned rv,
                                        std::uint64_t slot,
                                        bool combine)
{
    tb_result r;
    if (coded()) { // nr_ulsch counts non-finite LLRs as 0
        const auto u = d_ulsch->decode(llr, rv, c_init(slot), combine, d_bits.data());
        r.crc_ok = u.tb_crc_ok;
        r.parity_ok = u.parity_ok;
        r.code_blocks = u.code_blocks;
        r.cb_crc_ok = u.cb_crc_ok;
        r.mean_iterations = u.mean_iterations;
    } else {
        gold_sequence c(c_init(slot));
        c.generate_unpacked(d_bits.data(), d_A + 24);
        for (std::size_t i = 0; i < d_A + 24; i++) // ties (0, non-finite) decide 0 before descrambling
            d_bits[i] = static_cast<std::uint8_t>((std::isfinite(llr[i]) && llr[i] < 0.0f) != (d_bits[i] != 0));
        r.crc_ok = r.parity_ok = d_crc.check(d_bits.data(), d_A + 24);
    }
    if (!(r.crc_ok && r.parity_ok))
        return r;
    std::vector<std::uint8_t> bytes(tb_bytes()); // A is a multiple of 8
    for (std::size_t i = 0; i < bytes.size(); i++)
        bytes[i] = pack8(d_bits.data() + 8 * i);
    r.header_ok = r.sdu.read(bytes.data(), bytes.size());
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
