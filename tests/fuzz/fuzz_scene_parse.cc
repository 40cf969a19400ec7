/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// libFuzzer target: the scene text grammar (scene::parse, the parser behind Python's
// make_scene, GRC's scene parameter and nrsar-sim --scene / --target) on arbitrary bytes.
// Properties checked (a violation aborts, which libFuzzer reports as a crash):
//  - parse, validate, compute_extent and check_scenario throw only std::invalid_argument,
//    and its message is printable ASCII (Python turns it into a ValueError);
//  - a scene that validates prints back ("%.17g" fields) to a text that parses to the
//    same targets (the grammar reads what it writes).

#include <gnuradio/nrsar/params.h>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

using namespace gr::nrsar;

namespace {

void check_message(const std::invalid_argument& e)
{
    for (const char* p = e.what(); *p; ++p)
        if (*p < 0x20 || *p > 0x7e) {
            std::fprintf(stderr, "non-printable byte in message: %s\n", e.what());
            std::abort();
        }
}

std::string print(const scene& scn)
{
    std::string text;
    char buf[160];
    for (const auto& t : scn.targets) {
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g;", t.x_m, t.y_m, t.rcs,
                      t.phase_rad * (180.0 / M_PI));
        text += buf;
    }
    return text;
}

bool same_number(double a, double b)
{
    // The phase goes through degrees and back: allow a few ulps of it.
    return a == b || std::fabs(a - b) <= 1e-12 * std::max(std::fabs(a), std::fabs(b));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    scene scn;
    try {
        scn = scene::parse(text);
        scn.validate();
    } catch (const std::invalid_argument& e) {
        check_message(e);
        return 0;
    }
    // Round trip: what validates prints and parses back to the same scene.
    const scene again = scene::parse(print(scn));
    if (again.targets.size() != scn.targets.size())
        std::abort();
    for (std::size_t i = 0; i < scn.targets.size(); ++i) {
        const auto &a = scn.targets[i], &b = again.targets[i];
        if (a.x_m != b.x_m || a.y_m != b.y_m || a.rcs != b.rcs ||
            !same_number(a.phase_rad, b.phase_rad)) {
            std::fprintf(stderr, "round trip changed target %zu: %s\n", i, print(scn).c_str());
            std::abort();
        }
    }
    // The geometry checks on whatever numbers parsed (huge, tiny, negative, -0).
    try {
        const auto geo = geometry::preset("paper");
        compute_extent(geo, scn);
        check_scenario(numerology::preset("small"), geo, scn);
    } catch (const std::invalid_argument& e) {
        check_message(e);
    }
    return 0;
}
