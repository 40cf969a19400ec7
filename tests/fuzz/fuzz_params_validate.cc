/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// libFuzzer target: the shared parameter types (params.h) filled from arbitrary bytes, then
// validate() and check_scenario(). Properties (a violation aborts): only
// std::invalid_argument is thrown, and what validates really holds, checked in 64-bit
// arithmetic independently of the code under test (e.g. the SRS band fits the grid,
// the DMRS symbols are increasing and inside the slot).

#include <gnuradio/nrsar/params.h>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

using namespace gr::nrsar;

namespace {

// Reads fixed-size values from the input; zeros once it runs out.
struct reader {
    const std::uint8_t* data;
    std::size_t size;
    template <typename T>
    T get()
    {
        T value{};
        const std::size_t n = std::min(sizeof(T), size);
        std::memcpy(&value, data, n);
        data += n;
        size -= n;
        return value;
    }
    // Small values most of the time, any 32-bit value sometimes.
    unsigned small_or_any()
    {
        const auto tag = get<std::uint8_t>();
        return (tag & 3) ? get<std::uint8_t>() : get<std::uint32_t>();
    }
};

[[noreturn]] void violated(const char* what)
{
    std::fprintf(stderr, "property violated: %s\n", what);
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    reader in{ data, size };
    numerology num;
    num.subcarrier_spacing_hz = in.get<double>();
    num.num_subcarriers = in.small_or_any();
    num.fft_size = in.small_or_any();
    num.cp_samples = in.small_or_any();
    num.symbols_per_slot = in.small_or_any();
    num.slots_per_frame = in.small_or_any();
    try {
        num.validate();
    } catch (const std::invalid_argument&) {
        return 0;
    }
    if (!(std::isfinite(num.subcarrier_spacing_hz) && num.subcarrier_spacing_hz > 0) ||
        num.num_subcarriers < 1 || num.fft_size < num.num_subcarriers ||
        num.symbols_per_slot < 1 || num.slots_per_frame < 1)
        violated("numerology::validate accepted an invalid numerology");

    srs_config srs;
    srs.start_subcarrier = in.small_or_any();
    srs.num_rb = in.small_or_any();
    srs.comb = in.small_or_any();
    srs.comb_offset = in.small_or_any();
    srs.period_slots = in.small_or_any();
    srs.symbol_in_slot = in.small_or_any();
    try {
        srs.validate(num);
        const std::uint64_t end =
            std::uint64_t(srs.start_subcarrier) + std::uint64_t(srs.num_rb) * 12u;
        if (srs.num_rb < 1 || end > num.num_subcarriers || srs.comb < 1 ||
            srs.comb_offset >= srs.comb || srs.period_slots < 1 ||
            srs.symbol_in_slot >= num.symbols_per_slot)
            violated("srs_config::validate accepted a band that does not fit the grid");
    } catch (const std::invalid_argument&) {
    }

    dmrs_config dmrs;
    const unsigned count = in.get<std::uint8_t>() % 8;
    for (unsigned i = 0; i < count; ++i)
        dmrs.symbols.push_back(in.small_or_any());
    dmrs.scrambling_id = in.small_or_any();
    try {
        dmrs.validate(num);
        for (std::size_t i = 0; i < dmrs.symbols.size(); ++i)
            if (dmrs.symbols[i] >= num.symbols_per_slot ||
                (i > 0 && dmrs.symbols[i] <= dmrs.symbols[i - 1]))
                violated("dmrs_config::validate accepted bad symbols");
        if (dmrs.scrambling_id > 65535)
            violated("dmrs_config::validate accepted a scrambling id above 65535");
    } catch (const std::invalid_argument&) {
    }

    geometry geo;
    geo.carrier_hz = in.get<double>();
    geo.velocity_mps = in.get<double>();
    geo.height_m = in.get<double>();
    geo.track_start_m = in.get<double>();
    geo.aperture_s = in.get<double>();
    const unsigned symbols_per_pulse = in.small_or_any();
    try {
        check_scenario(num, geo, scene::preset("paper3"), symbols_per_pulse);
        geo.symbols_per_aperture(num);
        num.range_bin_m(num.fft_size);
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
