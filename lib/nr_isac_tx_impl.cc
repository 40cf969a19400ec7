/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "nr_isac_tx_impl.h"
#include "message_ports.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cstring>

namespace gr {
namespace nrsar {

namespace {

constexpr std::uint64_t max_start_symbol = std::uint64_t{ 1 } << 40;

// Checks everything the constructor needs before the base class is built (the output
// item size depends on num), so a bad parameter raises std::invalid_argument first.
int checked_itemsize(const numerology& num, std::uint64_t seed, std::uint64_t start_symbol)
{
    num.validate();
    if (start_symbol > max_start_symbol)
        throw_param("start_symbol",
                    start_symbol,
                    "must be in [0, 2^40] (about a year of symbols; keeps the PRBS bit "
                    "count of the symbols before it in 64 bits)");
    if (seed > kernel::gold_sequence::max_c_init)
        throw_param("seed",
                    seed,
                    "must be in [0, 2147483647] (the 31-bit c_init of TS 38.211 5.2.1)");
    return static_cast<int>(num.num_subcarriers * sizeof(gr_complex));
}
} // namespace

nr_isac_tx::sptr nr_isac_tx::make(const numerology& num,
                                  modulation mod,
                                  tx_mode mode,
                                  const srs_config& srs,
                                  std::uint64_t seed,
                                  const dmrs_config& dmrs,
                                  std::uint64_t start_symbol)
{
    return gnuradio::make_block_sptr<nr_isac_tx_impl>(
        num, mod, mode, srs, seed, dmrs, start_symbol);
}

nr_isac_tx_impl::nr_isac_tx_impl(const numerology& num,
                                 modulation mod,
                                 tx_mode mode,
                                 const srs_config& srs,
                                 std::uint64_t seed,
                                 const dmrs_config& dmrs,
                                 std::uint64_t start_symbol)
    : gr::block("nr_isac_tx",
                gr::io_signature::make(0, 1, sizeof(std::uint8_t)),
                gr::io_signature::make(1, 1, checked_itemsize(num, seed, start_symbol))),
      d_grid(num, mod, mode, srs, dmrs),
      d_prbs(static_cast<std::uint32_t>(seed)),
      d_start(start_symbol),
      d_symbol(start_symbol)
{
    // Input bytes have no per-symbol meaning: their tags are not carried to the grid.
    set_tag_propagation_policy(TPP_DONT);
    d_stage.reserve(d_grid.num_subcarriers() * d_grid.mapper().bits_per_symbol() / 8 + 16);
    message_port_register_in(pdus_port());
    set_msg_handler(pdus_port(), [this](const pmt::pmt_t& msg) { handle_pdu(msg); });
    // The stage always holds the PRBS from the next unmapped bit on, so starting the PRBS
    // at bit data_bits_before(start) gives the stream from symbol 0's bits.
    d_prbs.discard(d_grid.data_bits_before(start_symbol));
}

bool nr_isac_tx_impl::check_topology(int ninputs, int /*noutputs*/)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_stream_input = ninputs > 0;
    // the input starts at the first data bit of start_symbol's slot (the header)
    const std::uint64_t slot_start = d_start - d_start % d_grid.num().symbols_per_slot;
    d_skip_bits = d_stream_input ? static_cast<std::size_t>(d_grid.data_bits_before(d_start) -
                                                            d_grid.data_bits_before(slot_start))
                                 : 0;
    if (d_stream_input && d_grid.mode() == tx_mode::SRS)
        d_logger->warn("input 0 is connected but mode SRS carries no data: input ignored");
    return true;
}

void nr_isac_tx_impl::drop_pdu(const char* why)
{
    d_pdus_dropped++;
    if (!d_warned_drop) {
        d_logger->warn("dropping PDU ({}); further drops are only counted (pdus_dropped())",
                       why);
        d_warned_drop = true;
    }
}

void nr_isac_tx_impl::handle_pdu(const pmt::pmt_t& msg)
{
    gr::thread::scoped_lock guard(d_setlock);
    if (d_stream_input) {
        drop_pdu("input 0 is connected, PDUs are not used");
        return;
    }
    if (d_start > 0) {
        drop_pdu("start_symbol > 0: PDU bits are placed from symbol 0 on");
        return;
    }
    if (!pmt::is_pair(msg) || !pmt::is_u8vector(pmt::cdr(msg))) {
        drop_pdu("not a PDU: expected pmt pair (meta . u8vector)");
        return;
    }
    const pmt::pmt_t vec = pmt::cdr(msg);
    const std::size_t len = pmt::length(vec);
    if (len == 0)
        return;
    if (d_pdus.size() >= max_queued_pdus) {
        drop_pdu("queue of 64 PDUs full, newest dropped");
        return;
    }
    std::size_t io_len = 0;
    const std::uint8_t* data = pmt::u8vector_elements(vec, io_len);
    d_pdus.emplace_back(data, data + io_len);
    d_queued = static_cast<unsigned>(d_pdus.size());
}

bool nr_isac_tx_impl::stage_from_pdus_and_prbs(std::size_t need)
{
    bool used_prbs = false;
    while (staged_bits() < need) {
        const std::size_t missing = (need - staged_bits() + 7) / 8;
        const std::size_t old = d_stage.size();
        if (!d_pdus.empty()) {
            const auto& front = d_pdus.front();
            const std::size_t take = std::min(missing, front.size() - d_pdu_offset);
            d_stage.insert(d_stage.end(),
                           front.begin() + static_cast<std::ptrdiff_t>(d_pdu_offset),
                           front.begin() + static_cast<std::ptrdiff_t>(d_pdu_offset + take));
            d_pdu_offset += take;
            d_payload_bytes += take;
            if (d_pdu_offset == front.size()) {
                d_pdus.pop_front();
                d_pdu_offset = 0;
                d_queued = static_cast<unsigned>(d_pdus.size());
            }
        } else {
            d_stage.resize(old + missing);
            d_prbs.generate_packed(d_stage.data() + old, missing);
            used_prbs = true;
        }
    }
    return used_prbs;
}

void nr_isac_tx_impl::compact_stage()
{
    const std::size_t whole = d_stage_bit / 8;
    if (whole == 0)
        return;
    d_stage.erase(d_stage.begin(), d_stage.begin() + static_cast<std::ptrdiff_t>(whole));
    d_stage_bit -= 8 * whole;
}

void nr_isac_tx_impl::tag_symbol(std::uint64_t m)
{
    const std::uint64_t sps = d_grid.num().symbols_per_slot;
    if (m % sps != 0)
        return;
    const std::uint64_t slot = m / sps;
    const std::uint64_t item = m - d_start;
    add_item_tag(0, item, tags::symbol_key(), pmt::from_uint64(m));
    add_item_tag(0, item, tags::slot_key(), pmt::from_uint64(slot));
    const std::uint64_t spf = d_grid.num().slots_per_frame;
    if (slot % spf == 0)
        add_item_tag(0, item, tags::frame_key(), pmt::from_uint64(slot / spf));
}

void nr_isac_tx_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    if (ninput_items_required.empty())
        return;
    // Exactly the bytes the next noutput_items symbols need beyond the staged bits.
    std::size_t bits = d_skip_bits;
    for (int i = 0; i < noutput_items; i++)
        bits += d_grid.data_bits(d_symbol + static_cast<std::uint64_t>(i));
    const std::size_t have = staged_bits();
    ninput_items_required[0] = bits > have ? static_cast<int>((bits - have + 7) / 8) : 0;
}

int nr_isac_tx_impl::general_work(int noutput_items,
                                  gr_vector_int& ninput_items,
                                  gr_vector_const_void_star& input_items,
                                  gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const unsigned n_sc = d_grid.num_subcarriers();
    const std::uint8_t* in =
        d_stream_input ? static_cast<const std::uint8_t*>(input_items[0]) : nullptr;
    const std::size_t in_avail = d_stream_input ? static_cast<std::size_t>(ninput_items[0]) : 0;
    std::size_t in_used = 0;

    int produced = 0;
    for (; produced < noutput_items; produced++) {
        const std::uint64_t m = d_symbol;
        const std::size_t need = d_grid.data_bits(m) + d_skip_bits;
        if (staged_bits() < need) {
            if (d_stream_input) {
                const std::size_t nbytes = (need - staged_bits() + 7) / 8;
                if (in_avail - in_used < nbytes)
                    break;
                d_stage.insert(d_stage.end(), in + in_used, in + in_used + nbytes);
                in_used += nbytes;
                d_payload_bytes += nbytes;
            } else if (stage_from_pdus_and_prbs(need)) {
                d_prbs_symbols++;
            }
        }
        d_stage_bit += d_skip_bits; // once: the start slot's bits before start_symbol
        d_skip_bits = 0;
        d_stage_bit = d_grid.fill(
            m, d_stage.data(), d_stage_bit, out + static_cast<std::size_t>(produced) * n_sc);
        compact_stage();
        tag_symbol(m);
        d_symbol++;
    }
    if (d_stream_input)
        consume(0, static_cast<int>(in_used));
    return produced;
}

std::uint64_t nr_isac_tx_impl::payload_bytes_sent() const
{
    return d_payload_bytes;
}

std::uint64_t nr_isac_tx_impl::pdus_dropped() const
{
    return d_pdus_dropped;
}

std::uint64_t nr_isac_tx_impl::prbs_symbols() const
{
    return d_prbs_symbols;
}

unsigned nr_isac_tx_impl::queued_pdus() const
{
    return d_queued;
}

} /* namespace nrsar */
} /* namespace gr */
