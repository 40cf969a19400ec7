/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(tf_filter.h)                                               */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/tf_filter.h>
// pydoc.h is automatically generated in the build directory
#include <tf_filter_pydoc.h>

void bind_tf_filter(py::module& m)
{
    using tf_filter = gr::nrsar::tf_filter;

    py::class_<tf_filter,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<tf_filter>>(m, "tf_filter", D(tf_filter))

        .def(py::init(&tf_filter::make),
             py::arg("vlen"),
             py::arg("type") = gr::nrsar::filter_type::WF,
             py::arg("snr_db") = 20.0,
             py::arg("estimate_snr") = false,
             D(tf_filter, make))

        .def("set_filter_type",
             &tf_filter::set_filter_type,
             py::arg("type"),
             "Selects RF, MF or WF (takes effect on the next item).")
        .def("set_snr_db",
             &tf_filter::set_snr_db,
             py::arg("snr_db"),
             "Sets the SNR_in [dB] WF uses when it does not estimate it.")
        .def("set_estimate_snr",
             &tf_filter::set_estimate_snr,
             py::arg("estimate"),
             "Turns the method-of-moments SNR_in estimate on or off.")
        .def("set_constant_modulus_path",
             &tf_filter::set_constant_modulus_path,
             py::arg("on"),
             "Turns the constant-modulus shortcut (g = c conj(s) when every non-empty "
             "reference RE has the same |s|^2) on or off.")
        .def("constant_modulus_path",
             &tf_filter::constant_modulus_path,
             "Whether the constant-modulus shortcut is enabled.")
        .def("constant_modulus_items",
             &tf_filter::constant_modulus_items,
             "Items filtered by the constant-modulus shortcut so far.")
        .def("set_threads",
             &tf_filter::set_threads,
             py::arg("threads"),
             "1 (default) or 2: filter the second half of each work() call's items on a "
             "second thread.")
        .def("threads", &tf_filter::threads, "Threads per work() call.")
        .def("filter_type", &tf_filter::filter_type, "The filter in use.")
        .def("snr_db", &tf_filter::snr_db, "The given SNR_in [dB].")
        .def("estimate_snr", &tf_filter::estimate_snr, "Whether SNR_in is estimated.")
        .def("estimated_snr_db",
             &tf_filter::estimated_snr_db,
             "Latest SNR_in estimate [dB] (NaN before the first valid estimate).")
        .def("empty_re_count",
             &tf_filter::empty_re_count,
             "REs with an empty reference (|s|^2 = 0) so far.")
        .def("nonfinite_count",
             &tf_filter::nonfinite_count,
             "Non-finite input samples replaced by 0 so far.")
        .def("set_snr_prepass",
             &tf_filter::set_snr_prepass,
             py::arg("on"),
             "A strip's pre-pass: keep each item's SNR-estimator sums (snr_sums()) instead "
             "of filtering it (the output is zeros).")
        .def("snr_sums",
             &tf_filter::snr_sums,
             "The pre-pass's sums, four per item: sum |y|^2, sum |s|^2, sum |s|^4, "
             "sum |y|^2 |s|^2.")
        .def("snr_history", &tf_filter::snr_history, "The SNR estimator's state.")
        .def("set_snr_history",
             &tf_filter::set_snr_history,
             py::arg("history"),
             "Starts the SNR estimator from a history (snr_histories()), before the first "
             "item.")
        .def_static("snr_histories",
                    &tf_filter::snr_histories,
                    py::arg("vlen"),
                    py::arg("sums"),
                    py::arg("items"),
                    py::arg("history") = std::vector<double>(),
                    "The SNR estimator's history before each of `items` of a stream whose "
                    "pre-pass sums are `sums`, replayed from `history` (empty: the "
                    "stream's start; a strip task's start, docs/scale.md).");
}
