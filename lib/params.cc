/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/params.h>
#include "param_check.h"
#include <algorithm>
#include <charconv>
#include <clocale>
#include <cstdlib>
#include <locale.h>
#include <stdlib.h>
#include <cmath>
#include <sstream>
#include <system_error>

namespace gr {
namespace nrsar {

namespace {

template <typename T>
std::vector<std::string> names_of(const T& table)
{
    std::vector<std::string> names;
    for (const auto& entry : table)
        names.push_back(entry.first);
    return names;
}

template <typename T>
auto lookup(const T& table, const std::string& what, const std::string& name)
{
    for (const auto& entry : table)
        if (entry.first == name)
            return entry.second;
    std::ostringstream msg;
    msg << what << " preset '" << name << "' is unknown; known presets:";
    for (const auto& entry : table)
        msg << " " << entry.first;
    throw std::invalid_argument(msg.str());
}

const std::vector<std::pair<std::string, numerology>>& numerology_presets()
{
    // {Delta f, N, FFT size, CP samples, symbols/slot, slots/frame}
    static const std::vector<std::pair<std::string, numerology>> table = {
        { "paper", { 30e3, 3333, 4096, 1024, 14, 20 } },
        { "small", { 30e3, 512, 512, 128, 14, 20 } },
        { "tiny", { 30e3, 64, 64, 16, 14, 20 } },
        { "nr273", { 30e3, 3276, 4096, 288, 14, 20 } },
        { "sdr20", { 30e3, 612, 1024, 256, 14, 20 } },
    };
    return table;
}

const std::vector<std::pair<std::string, geometry>>& geometry_presets()
{
    // {fc, v, H, track start, aperture}
    static const std::vector<std::pair<std::string, geometry>> table = {
        { "paper", { 3.5e9, 50.0, 1000.0, 0.0, 2.0 } },
        { "short", { 3.5e9, 50.0, 1000.0, 0.0, 0.1 } },
    };
    return table;
}

const std::vector<std::pair<std::string, scene>>& scene_presets()
{
    static const std::vector<std::pair<std::string, scene>> table = {
        { "paper3", { { { 300.0, 100.0 }, { 250.0, 100.0 }, { 300.0, 140.0 } } } },
        { "single", { { { 300.0, 100.0 } } } },
    };
    return table;
}

} // namespace

double numerology::range_bin_m(unsigned nfft) const
{
    return speed_of_light / (2.0 * nfft * subcarrier_spacing_hz);
}

double numerology::max_unambiguous_range_m() const
{
    return speed_of_light / (2.0 * subcarrier_spacing_hz);
}

void numerology::validate() const
{
    check_finite_positive("subcarrier_spacing_hz", subcarrier_spacing_hz);
    check_at_least("num_subcarriers", num_subcarriers, 1u);
    if (fft_size < num_subcarriers) {
        std::ostringstream msg;
        msg << "fft_size = " << fft_size << " must be at least num_subcarriers = "
            << num_subcarriers;
        throw std::invalid_argument(msg.str());
    }
    check_at_least("symbols_per_slot", symbols_per_slot, 1u);
    check_at_least("slots_per_frame", slots_per_frame, 1u);
}

numerology numerology::preset(const std::string& name)
{
    return lookup(numerology_presets(), "numerology", name);
}

std::vector<std::string> numerology::preset_names()
{
    return names_of(numerology_presets());
}

void srs_config::validate(const numerology& num) const
{
    check_at_least("srs num_rb", num_rb, 1u);
    check_at_least("srs comb", comb, 1u);
    if (comb_offset >= comb)
        throw_param("srs comb_offset", comb_offset, "must be below comb = " + std::to_string(comb));
    check_at_least("srs period_slots", period_slots, 1u);
    if (symbol_in_slot >= num.symbols_per_slot)
        throw_param("srs symbol_in_slot",
                    symbol_in_slot,
                    "must be below symbols_per_slot = " + std::to_string(num.symbols_per_slot));
    // In 64 bits: start + num_rb * 12 wraps around in unsigned (found by
    // tests/fuzz/fuzz_params_validate: start 4294967048 with 255 RBs passed, ending at 2812).
    const std::uint64_t band_end =
        std::uint64_t(start_subcarrier) + std::uint64_t(num_rb) * 12u;
    if (band_end > num.num_subcarriers) {
        std::ostringstream msg;
        msg << "srs band [" << start_subcarrier << ", " << band_end
            << ") does not fit the " << num.num_subcarriers << " subcarriers of the grid";
        throw std::invalid_argument(msg.str());
    }
}

bool dmrs_config::is_dmrs_symbol(unsigned symbol_in_slot) const
{
    return std::find(symbols.begin(), symbols.end(), symbol_in_slot) != symbols.end();
}

void dmrs_config::validate(const numerology& num) const
{
    check_range("dmrs scrambling_id", scrambling_id, 0u, 65535u);
    for (std::size_t i = 0; i < symbols.size(); ++i) {
        if (symbols[i] >= num.symbols_per_slot)
            throw_param("dmrs symbols",
                        symbols[i],
                        "must be below symbols_per_slot = " + std::to_string(num.symbols_per_slot));
        if (i > 0 && symbols[i] <= symbols[i - 1])
            throw_param("dmrs symbols",
                        symbols[i],
                        "must be strictly increasing (follows " + std::to_string(symbols[i - 1]) +
                            ")");
    }
}

namespace {
const std::vector<std::pair<std::string, dmrs_config>>& dmrs_presets()
{
    static const std::vector<std::pair<std::string, dmrs_config>> table = {
        { "none", dmrs_config{} },
        { "pusch1", dmrs_config{ { 2 }, 0 } },
        { "pusch2", dmrs_config{ { 2, 11 }, 0 } },
        { "pusch4", dmrs_config{ { 2, 5, 8, 11 }, 0 } },
    };
    return table;
}
} // namespace

dmrs_config dmrs_config::preset(const std::string& name)
{
    return lookup(dmrs_presets(), "dmrs", name);
}

std::vector<std::string> dmrs_config::preset_names() { return names_of(dmrs_presets()); }

std::uint64_t geometry::symbols_per_aperture(const numerology& num) const
{
    return static_cast<std::uint64_t>(std::llround(aperture_s / num.symbol_s()));
}

double geometry::normalised_doppler(const numerology& num) const
{
    return 2.0 * velocity_mps * carrier_hz / (speed_of_light * num.subcarrier_spacing_hz);
}

void geometry::validate() const
{
    check_finite_positive("carrier_hz", carrier_hz);
    check_finite_positive("velocity_mps", velocity_mps);
    check_finite_positive("height_m", height_m);
    check_finite("track_start_m", track_start_m);
    check_finite_positive("aperture_s", aperture_s);
}

geometry geometry::preset(const std::string& name)
{
    return lookup(geometry_presets(), "geometry", name);
}

std::vector<std::string> geometry::preset_names() { return names_of(geometry_presets()); }

double point_target::slant_range_m(const geometry& geo, double platform_y_m) const
{
    const double dy = platform_y_m - y_m;
    return std::sqrt(x_m * x_m + geo.height_m * geo.height_m + dy * dy);
}

double scene::total_rcs() const
{
    double sum = 0.0;
    for (const auto& t : targets)
        sum += t.rcs;
    return sum;
}

void scene::validate() const
{
    if (targets.empty())
        throw std::invalid_argument("scene has no targets: at least 1 is needed");
    for (size_t i = 0; i < targets.size(); i++) {
        const auto& t = targets[i];
        const std::string prefix = "target " + std::to_string(i) + " ";
        check_finite(prefix + "x_m", t.x_m);
        check_finite(prefix + "y_m", t.y_m);
        check_finite(prefix + "phase_rad", t.phase_rad);
        if (!std::isfinite(t.rcs) || t.rcs < 0.0) {
            std::ostringstream msg;
            msg << prefix << "rcs = " << t.rcs << " must be finite and >= 0";
            throw std::invalid_argument(msg.str());
        }
    }
}

scene scene::preset(const std::string& name) { return lookup(scene_presets(), "scene", name); }

std::vector<std::string> scene::preset_names() { return names_of(scene_presets()); }

// The scene text grammar (make_scene in Python, GRC, the apps): "X,Y[,RCS[,PHASE_DEG]];...".
namespace {

constexpr const char* target_grammar = "X,Y[,RCS[,PHASE_DEG]]";

bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::string trim(const std::string& s)
{
    std::size_t b = 0, e = s.size();
    while (b < e && is_space(s[b]))
        ++b;
    while (e > b && is_space(s[e - 1]))
        --e;
    return s.substr(b, e - b);
}

// The text quoted in messages: at most 64 bytes, non-printable bytes as \xNN, so the
// message is printable ASCII (valid UTF-8 for Python's ValueError) whatever the input.
std::string quoted(const std::string& s)
{
    static const char hex[] = "0123456789abcdef";
    std::string out = "'";
    const std::size_t shown = std::min<std::size_t>(s.size(), 64);
    for (std::size_t i = 0; i < shown; ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out += static_cast<char>(c);
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (shown < s.size())
        out += "...";
    return out + "'";
}

// Python float() of a decimal string (SPEC 9 says the apps take what Python took):
// surrounding whitespace, one sign, digits with single '_' between digits, '.', exponent,
// inf / infinity / nan in any case. std::from_chars: locale-independent (Qt's setlocale
// cannot turn the decimal point into a comma). Returns false when the text is not one.
bool parse_number(const std::string& field, double& value, bool& out_of_range)
{
    out_of_range = false;
    std::string s = trim(field);
    std::string clean;
    clean.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '_') {
            if (i == 0 || i + 1 == s.size() || !is_digit(s[i - 1]) || !is_digit(s[i + 1]))
                return false;
            continue;
        }
        if (!(is_digit(s[i]) || s[i] == '.' || s[i] == 'e' || s[i] == 'E' || s[i] == '+' ||
              s[i] == '-' || std::isalpha(static_cast<unsigned char>(s[i]))))
            return false; // "nan(...)", hex digits after "0x" etc. are not Python floats
        clean += s[i];
    }
    std::size_t start = 0;
    if (!clean.empty() && clean[0] == '+')
        start = 1; // from_chars takes '-' only
    if (start == clean.size() || clean[start] == '+' || (start == 1 && clean[start] == '-'))
        return false; // "+", "++1", "+-1"
    const char* first = clean.data() + start;
    const char* last = clean.data() + clean.size();
    // Hexadecimal is not a Python float literal; from_chars(general) refuses "0x" anyway.
    const auto res = std::from_chars(first, last, value, std::chars_format::general);
    if (res.ec == std::errc::result_out_of_range && res.ptr == last) {
        // Python's float() reads an underflow as 0 or a denormal, as strtod does (in the
        // "C" locale, whatever the process's LC_NUMERIC); an overflow (Python: inf, which
        // validate() refuses) is refused here already, naming the text.
        static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", locale_t(0));
        const std::string text(first, last);
        const double v = strtod_l(text.c_str(), nullptr, c_locale);
        if (std::isinf(v)) {
            out_of_range = true;
            return false;
        }
        value = v;
        return true;
    }
    return res.ec == std::errc() && res.ptr == last;
}

} // namespace

point_target point_target::parse(const std::string& text, std::size_t index)
{
    static const char* const names[] = { "x_m", "y_m", "rcs", "phase_deg" };
    const std::string where = "target " + std::to_string(index) + " " + quoted(text);
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        fields.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
        if (comma == std::string::npos)
            break;
        start = comma + 1;
    }
    if (fields.size() < 2 || fields.size() > 4) {
        std::ostringstream msg;
        msg << where << ": has " << fields.size() << (fields.size() == 1 ? " field" : " fields")
            << "; must be " << target_grammar
            << " (ground range and along-track position in metres, RCS linear power, phase "
               "in degrees)";
        if (fields.size() == 1) {
            msg << " or a scene preset:";
            for (const auto& name : scene::preset_names())
                msg << " " << name;
        }
        throw std::invalid_argument(msg.str());
    }
    double v[4] = { 0.0, 0.0, 1.0, 0.0 };
    for (std::size_t i = 0; i < fields.size(); ++i) {
        bool out_of_range = false;
        if (!parse_number(fields[i], v[i], out_of_range)) {
            std::ostringstream msg;
            msg << where << ": " << names[i] << " " << quoted(trim(fields[i]))
                << (out_of_range ? " is out of the range of a double"
                                 : " is not a number");
            throw std::invalid_argument(msg.str());
        }
    }
    return point_target(v[0], v[1], v[2], v[3] * (M_PI / 180.0));
}

scene scene::parse(const std::string& text)
{
    const std::string name = trim(text);
    for (const auto& entry : scene_presets())
        if (entry.first == name)
            return entry.second;
    scene scn;
    std::size_t start = 0;
    for (;;) {
        const std::size_t semi = text.find(';', start);
        const std::string item =
            text.substr(start, semi == std::string::npos ? semi : semi - start);
        if (!trim(item).empty())
            scn.targets.push_back(point_target::parse(item, scn.targets.size()));
        if (semi == std::string::npos)
            break;
        start = semi + 1;
    }
    return scn;
}

scene_extent compute_extent(const geometry& geo, const scene& scn)
{
    scn.validate();
    scene_extent ext;
    ext.min_slant_range_m = INFINITY;
    ext.max_slant_range_m = 0.0;
    ext.min_doppler_hz = INFINITY;
    ext.max_doppler_hz = -INFINITY;
    const double y_first = geo.track_start_m;
    const double y_last = geo.track_start_m + geo.velocity_mps * geo.aperture_s;
    for (const auto& t : scn.targets) {
        // Range is convex along the track: the extremes are at the ends or abeam.
        const double y_abeam = std::clamp(t.y_m, y_first, y_last);
        const double r_first = t.slant_range_m(geo, y_first);
        const double r_last = t.slant_range_m(geo, y_last);
        ext.min_slant_range_m =
            std::min(ext.min_slant_range_m, t.slant_range_m(geo, y_abeam));
        ext.max_slant_range_m = std::max({ ext.max_slant_range_m, r_first, r_last });
        // Doppler 2 v (y_t - y_p) / (lambda R) is monotonic along the track.
        for (double y_p : { y_first, y_last }) {
            const double fd = 2.0 * geo.velocity_mps * (t.y_m - y_p) /
                              (geo.wavelength_m() * t.slant_range_m(geo, y_p));
            ext.min_doppler_hz = std::min(ext.min_doppler_hz, fd);
            ext.max_doppler_hz = std::max(ext.max_doppler_hz, fd);
        }
    }
    return ext;
}

std::vector<std::string> check_scenario(const numerology& num,
                                        const geometry& geo,
                                        const scene& scn,
                                        unsigned symbols_per_pulse)
{
    check_at_least("symbols_per_pulse", symbols_per_pulse, 1u);
    num.validate();
    geo.validate();
    const scene_extent ext = compute_extent(geo, scn);
    std::vector<std::string> warnings;

    const double round_trip_s = 2.0 * ext.max_slant_range_m / speed_of_light;
    if (round_trip_s > num.cp_s()) {
        std::ostringstream msg;
        msg << "cyclic prefix too short: the farthest target (slant range "
            << ext.max_slant_range_m << " m) has a round trip of " << round_trip_s * 1e6
            << " us, longer than Tcp = " << num.cp_s() * 1e6 << " us ("
            << num.cp_samples << " samples); the CP must cover ranges up to "
            << num.cp_s() * speed_of_light / 2.0 << " m";
        throw std::invalid_argument(msg.str());
    }
    const double eta = geo.normalised_doppler(num);
    if (eta >= 0.1) {
        std::ostringstream msg;
        msg << "normalised Doppler eta = 2 v fc / (c Delta f) = " << eta
            << " must be below 0.1 (v = " << geo.velocity_mps
            << " m/s, fc = " << geo.carrier_hz << " Hz, Delta f = "
            << num.subcarrier_spacing_hz << " Hz): inter-carrier interference";
        throw std::invalid_argument(msg.str());
    }
    if (ext.max_slant_range_m >= num.max_unambiguous_range_m()) {
        std::ostringstream msg;
        msg << "farthest slant range " << ext.max_slant_range_m
            << " m is beyond the unambiguous range c / (2 Delta f) = "
            << num.max_unambiguous_range_m() << " m";
        throw std::invalid_argument(msg.str());
    }
    const double pulse_rate_hz = num.prf_hz() / symbols_per_pulse;
    if (ext.doppler_bandwidth_hz() > pulse_rate_hz) {
        std::ostringstream msg;
        msg << "pulse rate " << pulse_rate_hz << " Hz (one pulse every " << symbols_per_pulse
            << " symbols) is below the scene's Doppler band of "
            << ext.doppler_bandwidth_hz() << " Hz [" << ext.min_doppler_hz << ", "
            << ext.max_doppler_hz << "]: the azimuth spectrum aliases";
        warnings.push_back(msg.str());
    }
    return warnings;
}

} // namespace nrsar
} // namespace gr
