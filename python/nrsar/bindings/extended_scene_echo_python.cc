/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

/***********************************************************************************/
/* Hand-written bindings: the hash 0 below turns GNU Radio's header-hash check off. */
/* BINDTOOL_GEN_AUTOMATIC(0)                                                       */
/* BINDTOOL_USE_PYGCCXML(0)                                                        */
/* BINDTOOL_HEADER_FILE(extended_scene_echo.h)                                     */
/* BINDTOOL_HEADER_FILE_HASH(0)                                                    */
/***********************************************************************************/

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;

#include <gnuradio/nrsar/extended_scene_echo.h>
#include <gnuradio/nrsar/kernel/extended_scene.h>
// pydoc.h is automatically generated in the build directory
#include <extended_scene_echo_pydoc.h>

#include <cstring>

void bind_extended_scene_echo(py::module& m)
{
    namespace k = gr::nrsar::kernel;
    using cvec = py::array_t<std::complex<float>, py::array::c_style | py::array::forcecast>;

    py::class_<k::reflectivity_map>(
        m,
        "reflectivity_map",
        "Reflectivity map on a ground grid: pixel (i, j) at (x0 + i dx, y0 + j dy), complex\n"
        "amplitude values[j, i] (|value|^2 = RCS); optional seeded CN(0, 1) speckle.")
        .def(py::init<>())
        .def_readwrite("nx", &k::reflectivity_map::nx)
        .def_readwrite("ny", &k::reflectivity_map::ny)
        .def_readwrite("dx", &k::reflectivity_map::dx)
        .def_readwrite("dy", &k::reflectivity_map::dy)
        .def_readwrite("x0", &k::reflectivity_map::x0)
        .def_readwrite("y0", &k::reflectivity_map::y0)
        .def_readwrite("speckle", &k::reflectivity_map::speckle)
        .def_readwrite("speckle_seed", &k::reflectivity_map::speckle_seed)
        .def_property(
            "values",
            [](const k::reflectivity_map& map) {
                cvec out({ std::size_t(map.ny), std::size_t(map.nx) });
                if (map.values.size() == std::size_t(map.nx) * map.ny)
                    std::memcpy(out.mutable_data(),
                                map.values.data(),
                                map.values.size() * sizeof(gr_complex));
                return out;
            },
            [](k::reflectivity_map& map, cvec a) {
                // A 2-D array sets ny, nx from its shape (rows = y); 1-D keeps them.
                if (a.ndim() == 2) {
                    map.ny = static_cast<unsigned>(a.shape(0));
                    map.nx = static_cast<unsigned>(a.shape(1));
                }
                map.values.assign(a.data(), a.data() + a.size());
            },
            "ny x nx complex amplitudes (numpy complex64; a 2-D array sets nx, ny)")
        .def("validate", &k::reflectivity_map::validate);

    py::enum_<k::beam_mode>(m, "beam_mode")
        .value("WHOLE_BLOCK", k::beam_mode::WHOLE_BLOCK)
        .value("AZIMUTH", k::beam_mode::AZIMUTH)
        .value("AZIMUTH_ELEVATION", k::beam_mode::AZIMUTH_ELEVATION);

    py::class_<k::antenna_beam>(m,
                                "antenna_beam",
                                "Real-aperture antenna, eqs. (1)-(3): two-way sinc^2 patterns.")
        .def(py::init<>())
        .def_readwrite("mode", &k::antenna_beam::mode)
        .def_readwrite("az_aperture_m", &k::antenna_beam::az_aperture_m)
        .def_readwrite("el_aperture_m", &k::antenna_beam::el_aperture_m)
        .def_readwrite("el_center_rad", &k::antenna_beam::el_center_rad)
        .def_readwrite("cutoff", &k::antenna_beam::cutoff)
        .def("validate", &k::antenna_beam::validate)
        .def("azimuth_beamwidth_rad", &k::antenna_beam::azimuth_beamwidth_rad, py::arg("geo"))
        .def("elevation_beamwidth_rad", &k::antenna_beam::elevation_beamwidth_rad, py::arg("geo"))
        .def("azimuth_coverage_m", &k::antenna_beam::azimuth_coverage_m, py::arg("geo"))
        .def("elevation_coverage_m", &k::antenna_beam::elevation_coverage_m, py::arg("geo"))
        .def("elevation_gain", &k::antenna_beam::elevation_gain, py::arg("geo"), py::arg("x_m"))
        .def("azimuth_gain",
             &k::antenna_beam::azimuth_gain,
             py::arg("geo"),
             py::arg("dy_m"),
             py::arg("range_m"));

    // The kernel itself, for benchmarks and the fast-vs-exact comparison from Python.
    py::class_<k::extended_scene>(m,
                                  "extended_scene_kernel",
                                  "kernel::extended_scene: H[n, m] of an extended scene.")
        .def(py::init([](const gr::nrsar::numerology& num,
                         const gr::nrsar::geometry& geo,
                         const gr::nrsar::scene& points,
                         const std::vector<k::reflectivity_map>& maps,
                         const k::antenna_beam& beam,
                         unsigned taps,
                         double oversampling,
                         const gr::nrsar::trajectory& path) {
                 return std::make_unique<k::extended_scene>(
                     num, geo, points, maps, beam, taps, oversampling, path);
             }),
             py::arg("num"),
             py::arg("geo"),
             py::arg("points"),
             py::arg("maps"),
             py::arg("beam") = k::antenna_beam(),
             py::arg("taps") = 8,
             py::arg("oversampling") = 2.0,
             py::arg("path") = gr::nrsar::trajectory())
        .def("num_scatterers", &k::extended_scene::num_scatterers)
        .def("grid_size", &k::extended_scene::grid_size)
        .def("total_power", &k::extended_scene::total_power)
        .def("platform_y", &k::extended_scene::platform_y, py::arg("m"))
        .def(
            "scatterers",
            [](const k::extended_scene& g) {
                const std::size_t K = g.num_scatterers();
                py::array_t<double> x(K), y(K);
                py::array_t<std::complex<double>> a(K);
                for (std::size_t i = 0; i < K; i++) {
                    x.mutable_at(i) = g.scatterer_x(i);
                    y.mutable_at(i) = g.scatterer_y(i);
                    a.mutable_at(i) = g.scatterer_amplitude(i);
                }
                return py::make_tuple(x, y, a);
            },
            "(x, y, amplitude) of the scatterers kept (after speckle and elevation gain)")
        .def(
            "reference",
            [](k::extended_scene& g, std::uint64_t m) {
                py::array_t<std::complex<float>> h(g.num_subcarriers());
                g.reference(m, h.mutable_data());
                return h;
            },
            py::arg("m"),
            "H[:, m] by the fast generator (complex64)")
        .def(
            "reference_exact",
            [](const k::extended_scene& g, std::uint64_t m) {
                py::array_t<std::complex<float>> h(g.num_subcarriers());
                g.reference_exact(m, h.mutable_data());
                return h;
            },
            py::arg("m"),
            "H[:, m] by the direct K x N sum in double (slow)");

    using blk = gr::nrsar::extended_scene_echo;
    py::class_<blk, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<blk>>(
        m, "extended_scene_echo", D(extended_scene_echo))
        .def(py::init(&blk::make),
             py::arg("num"),
             py::arg("geo"),
             py::arg("points"),
             py::arg("maps"),
             py::arg("beam") = k::antenna_beam(),
             py::arg("snr_db") = std::numeric_limits<double>::infinity(),
             py::arg("seed") = 0,
             py::arg("taps") = 8,
             py::arg("oversampling") = 2.0,
             py::arg("path") = gr::nrsar::trajectory(),
             D(extended_scene_echo, make))
        .def("set_snr_db", &blk::set_snr_db, py::arg("snr_db"), "New SNR per RE [dB].")
        .def("snr_db", &blk::snr_db)
        .def("noise_variance", &blk::noise_variance, "sigma^2, 0 without noise.")
        .def("total_power", &blk::total_power, "Sum of |a_k|^2 (the SNR's signal power).")
        .def("num_scatterers", &blk::num_scatterers)
        .def("grid_size", &blk::grid_size, "Size P of the slant-range grid and its FFT.")
        .def("nonfinite_count", &blk::nonfinite_count);
}
