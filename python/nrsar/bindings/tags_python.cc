/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(tags.h)                                                    */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */

#include <pybind11/pybind11.h>

namespace py = pybind11;

#include <gnuradio/nrsar/tags.h>

void bind_tags(py::module& m)
{
    using namespace gr::nrsar;
    // Keys as strings; compare them with pmt.eq(tag.key, pmt.intern(nrsar.tag_keys.symbol)).
    py::module t = m.def_submodule("tag_keys", "Stream tag and message keys of the module");
    t.attr("symbol") = pmt::symbol_to_string(tags::symbol_key());
    t.attr("slot") = pmt::symbol_to_string(tags::slot_key());
    t.attr("frame") = pmt::symbol_to_string(tags::frame_key());
    t.attr("range_axis") = pmt::symbol_to_string(tags::range_axis_key());
    t.attr("ground_range_axis") = pmt::symbol_to_string(tags::ground_range_axis_key());
    t.attr("nonfinite") = pmt::symbol_to_string(tags::nonfinite_key());
    t.attr("aperture") = pmt::symbol_to_string(tags::aperture_key());
    t.attr("azimuth_axis") = pmt::symbol_to_string(tags::azimuth_axis_key());
    t.attr("doppler_axis") = pmt::symbol_to_string(tags::doppler_axis_key());
    t.attr("pulse_interval") = pmt::symbol_to_string(tags::pulse_interval_key());
    // ofdm_sync
    t.attr("sync") = pmt::symbol_to_string(tags::sync_key());
    t.attr("gap") = pmt::symbol_to_string(tags::gap_key());
}
