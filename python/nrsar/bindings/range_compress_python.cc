/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(range_compress.h)                                          */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/range_compress.h>
// pydoc.h is automatically generated in the build directory
#include <range_compress_pydoc.h>

void bind_range_compress(py::module& m)
{
    using range_compress = gr::nrsar::range_compress;
    using gr::nrsar::filter_type;
    using gr::nrsar::range_compress_config;
    using win = gr::fft::window;

    py::class_<range_compress_config>(
        m, "range_compress_config", "Options of range_compress (tf_filter's and range_ifft's)")
        .def(py::init([](filter_type filter,
                         double snr_db,
                         bool estimate_snr,
                         unsigned fft_size,
                         win::win_type window,
                         double window_param,
                         double r_min_m,
                         double r_max_m,
                         bool unit_grid) {
                 range_compress_config c;
                 c.filter = filter;
                 c.snr_db = snr_db;
                 c.estimate_snr = estimate_snr;
                 c.fft_size = fft_size;
                 c.window = window;
                 c.window_param = window_param;
                 c.r_min_m = r_min_m;
                 c.r_max_m = r_max_m;
                 c.unit_grid = unit_grid;
                 return c;
             }),
             py::arg("filter") = filter_type::WF,
             py::arg("snr_db") = 20.0,
             py::arg("estimate_snr") = false,
             py::arg("fft_size") = 0u,
             py::arg("window") = win::WIN_RECTANGULAR,
             py::arg("window_param") = win::INVALID_WIN_PARAM,
             py::arg("r_min_m") = 0.0,
             py::arg("r_max_m") = 0.0,
             py::arg("unit_grid") = false,
             "range_compress_config with every field as a keyword (defaults as in C++)")
        .def_readwrite("filter", &range_compress_config::filter)
        .def_readwrite("snr_db", &range_compress_config::snr_db)
        .def_readwrite("estimate_snr", &range_compress_config::estimate_snr)
        .def_readwrite("fft_size", &range_compress_config::fft_size)
        .def_readwrite("window", &range_compress_config::window)
        .def_readwrite("window_param", &range_compress_config::window_param)
        .def_readwrite("r_min_m", &range_compress_config::r_min_m)
        .def_readwrite("r_max_m", &range_compress_config::r_max_m)
        .def_readwrite("unit_grid", &range_compress_config::unit_grid);

    py::class_<range_compress,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<range_compress>>(m, "range_compress", D(range_compress))

        .def(py::init(&range_compress::make),
             py::arg("num"),
             py::arg("cfg") = range_compress_config(),
             D(range_compress, make))

        .def("set_filter_type", &range_compress::set_filter_type, py::arg("type"))
        .def("set_snr_db", &range_compress::set_snr_db, py::arg("snr_db"))
        .def("set_estimate_snr", &range_compress::set_estimate_snr, py::arg("estimate"))
        .def("set_snr_history",
             &range_compress::set_snr_history,
             py::arg("history"),
             "tf_filter.set_snr_history: starts the SNR estimator from a history.")
        .def("snr_history", &range_compress::snr_history, "The SNR estimator's state.")
        .def("set_constant_modulus_path",
             &range_compress::set_constant_modulus_path,
             py::arg("on"),
             "Constant-modulus shortcut of tf_filter (default on).")
        .def("set_window",
             &range_compress::set_window,
             py::arg("window"),
             py::arg("window_param") = win::INVALID_WIN_PARAM,
             "Changes the window (re-tags the range axis).")
        .def("filter_type", &range_compress::filter_type)
        .def("snr_db", &range_compress::snr_db)
        .def("estimate_snr", &range_compress::estimate_snr)
        .def("estimated_snr_db",
             &range_compress::estimated_snr_db,
             "Latest SNR_in estimate [dB] (NaN before the first).")
        .def("constant_modulus_path", &range_compress::constant_modulus_path)
        .def("constant_modulus_items",
             &range_compress::constant_modulus_items,
             "Items filtered by the constant-modulus shortcut so far.")
        .def("empty_re_count",
             &range_compress::empty_re_count,
             "REs with an empty reference seen so far.")
        .def("nonfinite_count",
             &range_compress::nonfinite_count,
             "Non-finite input samples replaced by 0 so far.")
        .def("window", &range_compress::window)
        .def("window_param", &range_compress::window_param)
        .def("num_bins", &range_compress::num_bins, "K, range bins per output item.")
        .def("first_bin", &range_compress::first_bin, "First output bin of the transform.")
        .def("range_axis_first_m",
             &range_compress::range_axis_first_m,
             "Slant range of the first output bin [m].")
        .def("range_bin_m", &range_compress::range_bin_m, "Bin spacing [m].")
        .def("fft_size", &range_compress::fft_size)
        .def("coherent_gain", &range_compress::coherent_gain, "mean(w) of the window.");
}
