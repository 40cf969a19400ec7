/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(ofdm_demod.h)                                              */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/ofdm_demod.h>
// pydoc.h is automatically generated in the build directory
#include <ofdm_demod_pydoc.h>

void bind_ofdm_demod(py::module& m)
{
    using ofdm_demod = gr::nrsar::ofdm_demod;

    py::class_<ofdm_demod,
               gr::block,
               gr::basic_block,
               std::shared_ptr<ofdm_demod>>(m, "ofdm_demod", D(ofdm_demod))

        .def(py::init(&ofdm_demod::make),
             py::arg("num"),
             py::arg("fft_start") = -1,
             py::arg("tx_start_time") = -1.0,
             D(ofdm_demod, make))
        .def("fft_start", &ofdm_demod::fft_start, "FFT window start within the symbol.")
        .def("symbol_length",
             &ofdm_demod::symbol_length,
             "Input samples per symbol, cp_samples + fft_size.")
        .def("nonfinite_count",
             &ofdm_demod::nonfinite_count,
             "Non-finite input samples replaced by 0 so far.")
        .def("tx_start_time",
             &ofdm_demod::tx_start_time,
             "TX start time [s] of the rx_time alignment; negative = off.")
        .def("set_tx_start_time",
             &ofdm_demod::set_tx_start_time,
             py::arg("t"),
             "Sets the TX start time [s] (negative: alignment off); re-aligns from the last "
             "rx_time tag.")
        .def("aligned", &ofdm_demod::aligned, "True once an rx_time tag aligned the stream.")
        .def("next_symbol", &ofdm_demod::next_symbol, "Symbol index of the next output vector.")
        .def("lost_symbols",
             &ofdm_demod::lost_symbols,
             "Symbols output as zeros (late receiver start, overflow).")
        .def("dropped_samples",
             &ofdm_demod::dropped_samples,
             "Input samples dropped by the rx_time alignment.")
        .def("rx_time_tags", &ofdm_demod::rx_time_tags, "rx_time tags seen.");
}
