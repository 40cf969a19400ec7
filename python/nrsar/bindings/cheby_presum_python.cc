/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(cheby_presum.h)                                            */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/cheby_presum.h>
// pydoc.h is automatically generated in the build directory
#include <cheby_presum_pydoc.h>

void bind_cheby_presum(py::module& m)
{
    using gr::nrsar::presum_domain;
    using gr::nrsar::presum_method;
    using cheby_presum = gr::nrsar::cheby_presum;
    using gr::nrsar::kernel::presum_config;

    py::enum_<presum_method>(m, "presum_method", "Azimuth presumming method [P-2.2]")
        .value("CHEBY", presum_method::CHEBY)
        .value("DROP", presum_method::DROP)
        .value("BOXCAR", presum_method::BOXCAR)
        .value("FILTER_DROP", presum_method::FILTER_DROP)
        .value("LMS", presum_method::LMS)
        .export_values();
    py::enum_<presum_domain>(m, "presum_domain", "What one input vector element is")
        .value("RANGE", presum_domain::RANGE)
        .value("TF", presum_domain::TF)
        .export_values();

    py::class_<presum_config>(m, "presum_config", "Options of cheby_presum")
        .def(py::init([](presum_method method,
                         presum_domain domain,
                         unsigned decim,
                         unsigned num_taps,
                         double passband_hz,
                         double stopband_hz,
                         double stopband_weight,
                         unsigned symbols_per_pulse,
                         bool enforce_qpe_bound,
                         double lms_step,
                         std::uint64_t first_output) {
                 presum_config c;
                 c.method = method;
                 c.domain = domain;
                 c.decim = decim;
                 c.num_taps = num_taps;
                 c.passband_hz = passband_hz;
                 c.stopband_hz = stopband_hz;
                 c.stopband_weight = stopband_weight;
                 c.symbols_per_pulse = symbols_per_pulse;
                 c.enforce_qpe_bound = enforce_qpe_bound;
                 c.lms_step = lms_step;
                 c.first_output = first_output;
                 return c;
             }),
             py::arg("method") = presum_method::CHEBY,
             py::arg("domain") = presum_domain::RANGE,
             py::arg("decim") = 10u,
             py::arg("num_taps") = 0u,
             py::arg("passband_hz") = -1.0,
             py::arg("stopband_hz") = -1.0,
             py::arg("stopband_weight") = 10.0,
             py::arg("symbols_per_pulse") = 1u,
             py::arg("enforce_qpe_bound") = true,
             py::arg("lms_step") = 0.2,
             py::arg("first_output") = 0u,
             "presum_config with every field as a keyword (defaults as in C++)")
        .def_readwrite("method", &presum_config::method)
        .def_readwrite("domain", &presum_config::domain)
        .def_readwrite("decim", &presum_config::decim)
        .def_readwrite("num_taps", &presum_config::num_taps)
        .def_readwrite("passband_hz", &presum_config::passband_hz)
        .def_readwrite("stopband_hz", &presum_config::stopband_hz)
        .def_readwrite("stopband_weight", &presum_config::stopband_weight)
        .def_readwrite("symbols_per_pulse", &presum_config::symbols_per_pulse)
        .def_readwrite("enforce_qpe_bound", &presum_config::enforce_qpe_bound)
        .def_readwrite("lms_step", &presum_config::lms_step)
        .def_readwrite("first_output", &presum_config::first_output);

    py::class_<cheby_presum, gr::block, gr::basic_block, std::shared_ptr<cheby_presum>>(
        m, "cheby_presum", D(cheby_presum))

        .def(py::init(&cheby_presum::make),
             py::arg("num"),
             py::arg("geo"),
             py::arg("scn"),
             py::arg("num_bins") = 256,
             py::arg("first_range_m") = 0.0,
             py::arg("range_bin_m") = 1.0,
             py::arg("cfg") = presum_config(),
             py::arg("nav") = gr::nrsar::trajectory(),
             D(cheby_presum, make))
        .def_static("max_decim",
                    &cheby_presum::max_decim,
                    py::arg("num"),
                    py::arg("geo"),
                    py::arg("scn"),
                    py::arg("symbols_per_pulse") = 1,
                    "Largest D of eq. (P-36): PRF / (2 v) sqrt(lambda R0 / 2).")
        .def("decim", &cheby_presum::decim)
        .def("method", &cheby_presum::method)
        .def("domain", &cheby_presum::domain)
        .def("num_bins", &cheby_presum::num_bins)
        .def("num_taps", &cheby_presum::num_taps)
        .def("lookahead", &cheby_presum::lookahead, "Pulses after g D that output g needs.")
        .def("history", &cheby_presum::history, "Pulses before g D that output g needs.")
        .def("first_pulse",
             &cheby_presum::first_pulse,
             "The flight's pulse the input starts at (cfg.first_output: a strip's task).")
        .def("centre_offset",
             &cheby_presum::centre_offset,
             "Output g is centred on input pulse g D + centre_offset().")
        .def("taps", &cheby_presum::taps, "Applied taps, oldest pulse first.")
        .def("prototype", &cheby_presum::prototype, "Real low-pass prototype, DC gain D.")
        .def("passband_hz", &cheby_presum::passband_hz)
        .def("equiripple",
             &cheby_presum::equiripple,
             "True: Parks-McClellan prototype; false: Kaiser-windowed sinc fallback.")
        .def("stopband_hz", &cheby_presum::stopband_hz)
        .def("passband_ripple_db", &cheby_presum::passband_ripple_db)
        .def("stopband_atten_db", &cheby_presum::stopband_atten_db)
        .def("doppler_centroid_hz", &cheby_presum::doppler_centroid_hz)
        .def("phase_frequency_hz", &cheby_presum::phase_frequency_hz, py::arg("element"))
        .def("output_pulse_interval_s", &cheby_presum::output_pulse_interval_s)
        .def("compensation_phase",
             &cheby_presum::compensation_phase,
             py::arg("element"),
             py::arg("t_ref_s"),
             py::arg("offset"),
             "eq. (P-27) phase [rad]: 4 pi f (R(t_ref + offset T) - R(t_ref)) / c.")
        .def("warnings", &cheby_presum::warnings)
        .def("nonfinite_count", &cheby_presum::nonfinite_count)
        .def("follows_path",
             &cheby_presum::follows_path,
             "Whether the compensation follows the navigation path (False: the ideal line).")
        .def("phase_segment",
             &cheby_presum::phase_segment,
             "Pulses between exact phase rows (the last segment's, with a path).");
}
