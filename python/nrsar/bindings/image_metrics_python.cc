/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 */

/***********************************************************************************/
/* This file is hand-written (no block header): the image metrics of the second     */
/* paper's section 3.2.1 (kernel/image_metrics.h) as functions on numpy arrays, the */
/* same code nmse_probe reports with.                                               */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                        */
/* BINDTOOL_USE_PYGCCXML(0)                                                         */
/* BINDTOOL_HEADER_FILE(kernel/image_metrics.h)                                     */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                     */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace py = pybind11;

#include <gnuradio/nrsar/kernel/image_metrics.h>

void bind_image_metrics(py::module& m)
{
    using cimage = py::array_t<std::complex<float>, py::array::c_style | py::array::forcecast>;
    m.def(
        "image_entropy",
        [](cimage img) { return gr::nrsar::kernel::image_entropy(img.data(), img.size()); },
        py::arg("img"),
        "-sum D ln D, D = |I|^2 / sum |I|^2 (the second paper's section 3.2.1)");
    m.def(
        "edge_preservation_index",
        [](cimage x, cimage y) {
            if (x.ndim() != 2 || y.ndim() != 2 || x.shape(0) != y.shape(0) || x.shape(1) != y.shape(1))
                throw std::invalid_argument("x and y must be 2-D images of one shape");
            return gr::nrsar::kernel::edge_preservation_index(
                x.data(), y.data(), x.shape(0), x.shape(1));
        },
        py::arg("x"),
        py::arg("y"),
        "EPI of y against x: correlation coefficient of their amplitudes' 4-neighbour "
        "Laplacians over the interior pixels (the second paper's section 3.2.1)");
    m.def("nesz_db",
          &gr::nrsar::kernel::nesz_db,
          py::arg("noise_power"),
          py::arg("target_energy"),
          py::arg("rcs_m2"),
          py::arg("pixel_area_m2"),
          "10 log10(P_n sigma_ref / (E_t A)): NESZ by the integral method");
}
