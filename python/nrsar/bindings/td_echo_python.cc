/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(td_echo.h)                                                 */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/td_echo.h>
// pydoc.h is automatically generated in the build directory
#include <td_echo_pydoc.h>

void bind_td_echo(py::module& m)
{
    using td_echo = gr::nrsar::td_echo;

    py::class_<td_echo, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<td_echo>>(
        m, "td_echo", D(td_echo))

        .def(py::init(&td_echo::make),
             py::arg("num"),
             py::arg("geo"),
             py::arg("scn"),
             py::arg("snr_db") = std::numeric_limits<double>::infinity(),
             py::arg("seed") = 0,
             py::arg("taps") = 32,
             py::arg("kaiser_beta") = -1.0,
             py::arg("beam") = gr::nrsar::kernel::antenna_beam(),
             py::arg("path") = gr::nrsar::trajectory(),
             D(td_echo, make))

        .def("set_snr_db",
             &td_echo::set_snr_db,
             py::arg("snr_db"),
             "New SNR per RE [dB] (+inf: no noise).")
        .def("snr_db", &td_echo::snr_db, "SNR per RE [dB].")
        .def("noise_variance",
             &td_echo::noise_variance,
             "sigma^2 per sample (= per RE) = total RCS / 10^(snr_db/10), 0 without noise.")
        .def("set_scene",
             &td_echo::set_scene,
             py::arg("scn"),
             "New scene, checked with check_scenario.")
        .def("get_scene", &td_echo::get_scene, "The current scene.")
        .def("taps", &td_echo::taps, "Fractional-delay FIR length.")
        .def("beam", &td_echo::beam, "The antenna beam (illumination) in use.")
        .def("path", &td_echo::path, "The true flight path (empty: the ideal line).")
        .def("kaiser_beta", &td_echo::kaiser_beta, "Kaiser window parameter in use.")
        .def("nonfinite_count",
             &td_echo::nonfinite_count,
             "Non-finite input samples zeroed so far.")
        .def("dropped_paths",
             &td_echo::dropped_paths,
             "(target, symbol) pairs left out: delay longer than one OFDM symbol.");
}
