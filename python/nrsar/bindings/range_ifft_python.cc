/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(range_ifft.h)                                              */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/range_ifft.h>
// pydoc.h is automatically generated in the build directory
#include <range_ifft_pydoc.h>

void bind_range_ifft(py::module& m)
{
    using range_ifft = gr::nrsar::range_ifft;
    using win = gr::fft::window;

    py::class_<range_ifft,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<range_ifft>>(m, "range_ifft", D(range_ifft))

        .def(py::init(&range_ifft::make),
             py::arg("num"),
             py::arg("fft_size") = 0,
             py::arg("window") = win::WIN_RECTANGULAR,
             py::arg("window_param") = win::INVALID_WIN_PARAM,
             py::arg("r_min_m") = 0.0,
             py::arg("r_max_m") = 0.0,
             D(range_ifft, make))

        .def_static("fast_fft_size",
                    &range_ifft::fast_fft_size,
                    py::arg("n"),
                    "Smallest 2^a 3^b 5^c 7^d >= n: an FFT size FFTW runs fast.")
        .def("set_window",
             &range_ifft::set_window,
             py::arg("window"),
             py::arg("window_param") = win::INVALID_WIN_PARAM,
             "Changes the window (re-tags the range axis).")
        .def("window", &range_ifft::window)
        .def("window_param", &range_ifft::window_param)
        .def("num_bins", &range_ifft::num_bins, "K, range bins per output item.")
        .def("first_bin", &range_ifft::first_bin, "First output bin of the transform.")
        .def("range_axis_first_m",
             &range_ifft::range_axis_first_m,
             "Slant range of the first output bin [m].")
        .def("range_bin_m", &range_ifft::range_bin_m, "Bin spacing [m].")
        .def("fft_size", &range_ifft::fft_size)
        .def("coherent_gain", &range_ifft::coherent_gain, "mean(w) of the window.")
        .def("nonfinite_count",
             &range_ifft::nonfinite_count,
             "Non-finite input samples replaced by 0 so far.")
        .def("set_threads",
             &range_ifft::set_threads,
             py::arg("threads"),
             "1 (default) or 2: transform the second half of each work() call's symbols on "
             "a second thread (own FFT plan).")
        .def("threads", &range_ifft::threads, "Threads per work() call.");

    m.def("fast_fft_size",
          &range_ifft::fast_fft_size,
          py::arg("n"),
          "Smallest 2^a 3^b 5^c 7^d >= n: an FFT size FFTW runs fast.");
}
