/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(params.h)                                                  */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/params.h>

void bind_params(py::module& m)
{
    using namespace gr::nrsar;

    py::enum_<modulation>(m, "modulation", "Constellation (3GPP TS 38.211 5.1, unit power)")
        .value("QPSK", modulation::QPSK)
        .value("QAM16", modulation::QAM16)
        .value("QAM64", modulation::QAM64)
        .value("QAM256", modulation::QAM256)
        .value("PSK8", modulation::PSK8)
        .value("PSK16", modulation::PSK16)
        .export_values();

    py::enum_<tx_mode>(m, "tx_mode", "What the transmit grid carries")
        .value("DATA", tx_mode::DATA)
        .value("SRS", tx_mode::SRS)
        .value("DATA_SRS", tx_mode::DATA_SRS)
        .export_values();

    py::enum_<filter_type>(m, "filter_type", "Per-RE filter, eq. (25)")
        .value("RF", filter_type::RF)
        .value("MF", filter_type::MF)
        .value("WF", filter_type::WF)
        .export_values();

    py::class_<numerology>(m, "numerology", "OFDM numerology shared by every block")
        .def(py::init<>())
        .def_readwrite("subcarrier_spacing_hz", &numerology::subcarrier_spacing_hz)
        .def_readwrite("num_subcarriers", &numerology::num_subcarriers)
        .def_readwrite("fft_size", &numerology::fft_size)
        .def_readwrite("cp_samples", &numerology::cp_samples)
        .def_readwrite("symbols_per_slot", &numerology::symbols_per_slot)
        .def_readwrite("slots_per_frame", &numerology::slots_per_frame)
        .def("sample_rate_hz", &numerology::sample_rate_hz)
        .def("useful_symbol_s", &numerology::useful_symbol_s)
        .def("cp_s", &numerology::cp_s)
        .def("symbol_s", &numerology::symbol_s)
        .def("prf_hz", &numerology::prf_hz)
        .def("bandwidth_hz", &numerology::bandwidth_hz)
        .def("dc_subcarrier", &numerology::dc_subcarrier)
        .def("range_bin_m", &numerology::range_bin_m, py::arg("nfft"))
        .def("max_unambiguous_range_m", &numerology::max_unambiguous_range_m)
        .def("validate", &numerology::validate)
        .def_static("preset", &numerology::preset, py::arg("name"))
        .def_static("preset_names", &numerology::preset_names)
        .def("__repr__", [](const numerology& n) {
            return "numerology(subcarrier_spacing_hz=" +
                   std::to_string(n.subcarrier_spacing_hz) +
                   ", num_subcarriers=" + std::to_string(n.num_subcarriers) +
                   ", fft_size=" + std::to_string(n.fft_size) +
                   ", cp_samples=" + std::to_string(n.cp_samples) + ")";
        });

    py::class_<srs_config>(m, "srs_config", "SRS comb pilot layout")
        .def(py::init<>())
        .def_readwrite("start_subcarrier", &srs_config::start_subcarrier)
        .def_readwrite("num_rb", &srs_config::num_rb)
        .def_readwrite("comb", &srs_config::comb)
        .def_readwrite("comb_offset", &srs_config::comb_offset)
        .def_readwrite("period_slots", &srs_config::period_slots)
        .def_readwrite("symbol_in_slot", &srs_config::symbol_in_slot)
        .def("num_subcarriers", &srs_config::num_subcarriers)
        .def("validate", &srs_config::validate, py::arg("num"));

    py::class_<dmrs_config>(m, "dmrs_config", "PUSCH DMRS layout (type 1, comb 2)")
        .def(py::init<>())
        .def_readwrite("symbols", &dmrs_config::symbols)
        .def_readwrite("scrambling_id", &dmrs_config::scrambling_id)
        .def("enabled", &dmrs_config::enabled)
        .def("is_dmrs_symbol", &dmrs_config::is_dmrs_symbol, py::arg("symbol_in_slot"))
        .def("validate", &dmrs_config::validate, py::arg("num"))
        .def_static("preset", &dmrs_config::preset, py::arg("name"))
        .def_static("preset_names", &dmrs_config::preset_names)
        .def("__repr__", [](const dmrs_config& d) {
            std::string s = "dmrs_config(symbols=[";
            for (std::size_t i = 0; i < d.symbols.size(); ++i)
                s += (i ? ", " : "") + std::to_string(d.symbols[i]);
            return s + "], scrambling_id=" + std::to_string(d.scrambling_id) + ")";
        });

    py::class_<geometry>(m, "geometry", "Platform geometry and aperture")
        .def(py::init<>())
        .def_readwrite("carrier_hz", &geometry::carrier_hz)
        .def_readwrite("velocity_mps", &geometry::velocity_mps)
        .def_readwrite("height_m", &geometry::height_m)
        .def_readwrite("track_start_m", &geometry::track_start_m)
        .def_readwrite("aperture_s", &geometry::aperture_s)
        .def("wavelength_m", &geometry::wavelength_m)
        .def("symbols_per_aperture", &geometry::symbols_per_aperture, py::arg("num"))
        .def("normalised_doppler", &geometry::normalised_doppler, py::arg("num"))
        .def("validate", &geometry::validate)
        .def_static("preset", &geometry::preset, py::arg("name"))
        .def_static("preset_names", &geometry::preset_names);

    py::class_<point_target>(m, "point_target", "Point scatterer on the ground")
        .def(py::init<>())
        .def(py::init<double, double, double, double>(),
             py::arg("x_m"),
             py::arg("y_m"),
             py::arg("rcs") = 1.0,
             py::arg("phase_rad") = 0.0)
        .def_readwrite("x_m", &point_target::x_m)
        .def_readwrite("y_m", &point_target::y_m)
        .def_readwrite("rcs", &point_target::rcs)
        .def_readwrite("phase_rad", &point_target::phase_rad)
        .def("slant_range_m",
             &point_target::slant_range_m,
             py::arg("geo"),
             py::arg("platform_y_m"))
        .def_static("parse",
                    &point_target::parse,
                    py::arg("text"),
                    py::arg("index") = 0,
                    "'X,Y[,RCS[,PHASE_DEG]]' -> point_target; ValueError names index, field, text")
        .def("__repr__", [](const point_target& t) {
            return "point_target(" + std::to_string(t.x_m) + ", " + std::to_string(t.y_m) +
                   ", " + std::to_string(t.rcs) + ")";
        });

    py::class_<scene>(m, "scene", "Point-target scene; the first target is the reference")
        .def(py::init<>())
        .def(py::init([](const std::vector<point_target>& targets) {
                 return scene{ targets };
             }),
             py::arg("targets"))
        .def_readwrite("targets", &scene::targets)
        .def("total_rcs", &scene::total_rcs)
        .def("validate", &scene::validate)
        .def_static("preset", &scene::preset, py::arg("name"))
        .def_static("preset_names", &scene::preset_names)
        .def_static("parse",
                    &scene::parse,
                    py::arg("text"),
                    "Preset name or 'X,Y[,RCS[,PHASE_DEG]];...' -> scene (not validated)");

    py::class_<scene_extent>(m, "scene_extent", "Slant-range and Doppler extent of a scene")
        .def_readonly("min_slant_range_m", &scene_extent::min_slant_range_m)
        .def_readonly("max_slant_range_m", &scene_extent::max_slant_range_m)
        .def_readonly("min_doppler_hz", &scene_extent::min_doppler_hz)
        .def_readonly("max_doppler_hz", &scene_extent::max_doppler_hz)
        .def("doppler_bandwidth_hz", &scene_extent::doppler_bandwidth_hz);

    m.def("compute_extent", &compute_extent, py::arg("geo"), py::arg("scn"));
    m.def("check_scenario",
          &check_scenario,
          py::arg("num"),
          py::arg("geo"),
          py::arg("scn"),
          py::arg("symbols_per_pulse") = 1,
          "Raise ValueError when the geometry breaks the TF echo model; return warnings");
    m.attr("speed_of_light") = speed_of_light;
}
