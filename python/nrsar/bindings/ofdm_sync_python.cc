/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(ofdm_sync.h)                                              */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/ofdm_sync.h>
// pydoc.h is automatically generated in the build directory
#include <ofdm_sync_pydoc.h>

void bind_ofdm_sync(py::module& m)
{
    using ofdm_sync = gr::nrsar::ofdm_sync;

    py::class_<ofdm_sync, gr::block, gr::basic_block, std::shared_ptr<ofdm_sync>>(
        m, "ofdm_sync", D(ofdm_sync))

        .def(py::init(&ofdm_sync::make),
             py::arg("num"),
             py::arg("dmrs"),
             py::arg("threshold") = 0.1,
             py::arg("backoff") = 0.125,
             D(ofdm_sync, make))
        .def("locked", &ofdm_sync::locked, "True once the current acquisition has locked.")
        .def("cfo_hz", &ofdm_sync::cfo_hz, "CFO estimate [Hz] (0 before lock).")
        .def("timing_samples",
             &ofdm_sync::timing_samples,
             "Input sample index of the estimated start of the first detected DMRS symbol "
             "(-1 before lock).")
        .def("start_samples",
             &ofdm_sync::start_samples,
             "Input sample index that became output sample 0 (may be negative).")
        .def("metric", &ofdm_sync::metric, "Peak Schmidl & Cox metric of the lock.")
        .def("threshold", &ofdm_sync::threshold)
        .def("set_threshold",
             &ofdm_sync::set_threshold,
             py::arg("threshold"),
             "Detection threshold for the next acquisition, in (0, 1).")
        .def("backoff", &ofdm_sync::backoff)
        .def("reset", &ofdm_sync::reset, "Starts a new acquisition at the next input sample.")
        .def("nonfinite_count",
             &ofdm_sync::nonfinite_count,
             "Non-finite input samples replaced by 0 so far.")
        .def("lost_samples",
             &ofdm_sync::lost_samples,
             "Samples lost in gaps: exact from rx_time jumps, plus the shift (modulo a slot) a "
             "re-acquisition after a lost lock found.")
        .def("reacquisitions",
             &ofdm_sync::reacquisitions,
             "Times the slot grid was re-established after a gap or a lost lock.")
        .def("lock_losses",
             &ofdm_sync::lock_losses,
             "Times the per-slot DMRS check (or an rx_time going back) lost the lock.")
        .def("skipped_slots",
             &ofdm_sync::skipped_slots,
             "Slots with lost samples, or cut by a lost lock, not output whole.")
        .def("skipped_symbols",
             &ofdm_sync::skipped_symbols,
             "Symbols from the one a gap cuts to the resumed slot's first.")
        .def("rx_time_gaps",
             &ofdm_sync::rx_time_gaps,
             "rx_time stamps that did not continue the previous one (overflows).");
}
