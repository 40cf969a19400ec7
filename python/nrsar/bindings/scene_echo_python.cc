/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(scene_echo.h)                                              */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/scene_echo.h>
// pydoc.h is automatically generated in the build directory
#include <scene_echo_pydoc.h>

void bind_scene_echo(py::module& m)
{
    using scene_echo = gr::nrsar::scene_echo;

    py::class_<scene_echo,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<scene_echo>>(m, "scene_echo", D(scene_echo))

        .def(py::init(&scene_echo::make),
             py::arg("num"),
             py::arg("geo"),
             py::arg("scn"),
             py::arg("snr_db") = std::numeric_limits<double>::infinity(),
             py::arg("seed") = 0,
             py::arg("path") = gr::nrsar::trajectory(),
             D(scene_echo, make))

        .def("set_snr_db",
             &scene_echo::set_snr_db,
             py::arg("snr_db"),
             "New SNR per RE [dB] (+inf: no noise).")
        .def("snr_db", &scene_echo::snr_db, "SNR per RE [dB].")
        .def("noise_variance",
             &scene_echo::noise_variance,
             "sigma^2 = total RCS / 10^(snr_db/10), 0 without noise.")
        .def("set_scene",
             &scene_echo::set_scene,
             py::arg("scn"),
             "New scene, checked with check_scenario.")
        .def("get_scene", &scene_echo::get_scene, "The current scene.")
        .def("path", &scene_echo::path, "The true flight path (empty: the ideal line).")
        .def("nonfinite_count",
             &scene_echo::nonfinite_count,
             "Non-finite input samples zeroed so far.")
        .def("set_threads",
             &scene_echo::set_threads,
             py::arg("threads"),
             "Threads computing the echo: 1 (default) or 2.")
        .def("threads", &scene_echo::threads, "Threads computing the echo.")
        .def("set_reference_only",
             &scene_echo::set_reference_only,
             py::arg("on"),
             "out0 carries the reference H (S = 1, no noise), out1 unconnected; Y not computed.")
        .def("reference_only", &scene_echo::reference_only, "Whether out0 is the reference.");
}
