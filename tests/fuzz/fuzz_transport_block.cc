/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// libFuzzer target: arbitrary bytes as LLRs and as TB bytes (MAC PDU) into transport_block_codec
// decode() and parse() (uncoded and LDPC). Built and run by `make fuzz` (tests/fuzz/README.md).

#include <gnuradio/nrsar/kernel/pusch_rx.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <cstdint>
#include <cstring>
#include <vector>

using gr::nrsar::kernel::transport_block_codec;

namespace {
gr::nrsar::pusch_config tiny(gr::nrsar::pusch_coding coding)
{
    gr::nrsar::pusch_config c;
    c.num = gr::nrsar::numerology::preset("tiny");
    c.coding = coding;
    return c;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static transport_block_codec uncoded(tiny(gr::nrsar::pusch_coding::NONE));
    static transport_block_codec coded(tiny(gr::nrsar::pusch_coding::NR_LDPC));
    if (size < 1)
        return 0;
    const std::uint8_t mode = data[0];
    data++;
    size--;
    // 1) bytes as a TB (the MAC PDU parser), zero-extended to the TB length
    {
        std::vector<std::uint8_t> tb(uncoded.tb_bytes(), 0);
        std::memcpy(tb.data(), data, std::min(size, tb.size()));
        gr::nrsar::kernel::mac_sdu sdu;
        if (sdu.read(tb.data(), tb.size()) && sdu.data.size() + 4 > tb.size())
            __builtin_trap();
    }
    // 2) bytes as LLRs: signed bytes, or raw float bit patterns (NaN, inf, denormals)
    auto& codec = (mode & 1) ? coded : uncoded;
    std::vector<float> llr(codec.slot_bits(), 0.0f);
    if (mode & 2) {
        std::memcpy(llr.data(), data, std::min(size, llr.size() * sizeof(float)));
    } else {
        for (std::size_t i = 0; i < std::min(size, llr.size()); i++)
            llr[i] = static_cast<float>(static_cast<std::int8_t>(data[i]));
    }
    const auto r = codec.decode(llr.data(), (mode >> 2) & 3, mode >> 4, codec.coded() && (mode & 8));
    if (r.header_ok && r.sdu.data.size() > codec.payload_bytes())
        __builtin_trap();
    // 3) bytes as a received slot (raw float bits: NaN, inf, huge values) into the whole
    //    receiver kernel: channel estimate, equaliser, soft demapper, decoder
    if (mode & 4) {
        static gr::nrsar::kernel::pusch_rx rx(tiny(gr::nrsar::pusch_coding::NR_LDPC));
        std::vector<gr_complex> grid(14 * 64, gr_complex(0.0f, 0.0f));
        std::memcpy(grid.data(), data, std::min(size, grid.size() * sizeof(gr_complex)));
        const auto s = rx.process(grid.data(), mode >> 3);
        if (s.tb.header_ok && s.tb.sdu.data.size() > rx.codec().payload_bytes())
            __builtin_trap();
    }
    return 0;
}
