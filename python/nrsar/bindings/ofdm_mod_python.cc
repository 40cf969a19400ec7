/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(ofdm_mod.h)                                              */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/ofdm_mod.h>
// pydoc.h is automatically generated in the build directory
#include <ofdm_mod_pydoc.h>

void bind_ofdm_mod(py::module& m)
{
    using ofdm_mod = gr::nrsar::ofdm_mod;

    py::class_<ofdm_mod,
               gr::sync_interpolator,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<ofdm_mod>>(m, "ofdm_mod", D(ofdm_mod))

        .def(py::init(&ofdm_mod::make), py::arg("num"), D(ofdm_mod, make))
        .def("symbol_length",
             &ofdm_mod::symbol_length,
             "Output samples per symbol, cp_samples + fft_size.")
        .def("nonfinite_count",
             &ofdm_mod::nonfinite_count,
             "Non-finite input REs replaced by 0 so far.");
}
