/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 */

#include <pybind11/pybind11.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

namespace py = pybind11;

// Headers for binding functions
/**************************************/
// The following comment block is used for
// gr_modtool to insert function prototypes
// Please do not delete
/**************************************/
// BINDING_FUNCTION_PROTOTYPES(
    void bind_params(py::module& m);
    void bind_tags(py::module& m);
    void bind_nr_isac_tx(py::module& m);
    void bind_scene_echo(py::module& m);
    void bind_tf_filter(py::module& m);
    void bind_range_ifft(py::module& m);
    void bind_range_compress(py::module& m);
    void bind_rd_focuser(py::module& m);
    void bind_nmse_probe(py::module& m);
    void bind_image_metrics(py::module& m);
    void bind_cheby_presum(py::module& m);
    void bind_extended_scene_echo(py::module& m);
    void bind_pusch_encoder(py::module& m);
    void bind_pusch_receiver(py::module& m);
    void bind_nr_coding(py::module& m);
    void bind_ofdm_mod(py::module& m);
    void bind_ofdm_demod(py::module& m);
    void bind_ofdm_sync(py::module& m);
    void bind_td_echo(py::module& m);
    void bind_image_sink(py::module& m);
    void bind_trajectory(py::module& m);
    void bind_bp_focuser(py::module& m);
    void bind_autofocus(py::module& m);
    void bind_uplink_channel(py::module& m);
// ) END BINDING_FUNCTION_PROTOTYPES


// We need this hack because import_array() returns NULL
// for newer Python versions.
// This function is also necessary because it ensures access to the C API
// and removes a warning.
void* init_numpy()
{
    import_array();
    return NULL;
}

PYBIND11_MODULE(nrsar_python, m)
{
    // Initialize the numpy C API
    // (otherwise we will see segmentation faults)
    init_numpy();

    // Allow access to base block methods
    py::module::import("gnuradio.gr");
    // Window types (gr::fft::window::win_type) are taken from gnuradio.fft.
    py::module::import("gnuradio.fft");

    /**************************************/
    // The following comment block is used for
    // gr_modtool to insert binding function calls
    // Please do not delete
    /**************************************/
    // BINDING_FUNCTION_CALLS(
    bind_params(m);
    bind_tags(m);
    bind_trajectory(m); // before the blocks whose make() defaults to an empty path
    bind_nr_isac_tx(m);
    bind_scene_echo(m);
    bind_tf_filter(m);
    bind_range_ifft(m);
    bind_range_compress(m);
    bind_rd_focuser(m);
    bind_nmse_probe(m);
    bind_image_metrics(m);
    bind_cheby_presum(m);
    bind_extended_scene_echo(m);
    bind_pusch_encoder(m);
    bind_pusch_receiver(m);
    bind_nr_coding(m);
    bind_ofdm_mod(m);
    bind_ofdm_demod(m);
    bind_ofdm_sync(m);
    bind_td_echo(m);
    bind_image_sink(m);
    bind_bp_focuser(m);
    bind_autofocus(m);
    bind_uplink_channel(m);
    // ) END BINDING_FUNCTION_CALLS
}