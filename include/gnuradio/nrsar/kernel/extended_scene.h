/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_EXTENDED_SCENE_H
#define INCLUDED_NRSAR_KERNEL_EXTENDED_SCENE_H

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/gaussian_noise.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <volk/volk_alloc.hh>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief A reflectivity map on a regular ground grid (z = 0).
 *
 * Pixel (i, j), i = 0 .. nx-1 along x (ground range), j = 0 .. ny-1 along y (along
 * track), is a point scatterer at (x0 + i dx, y0 + j dy) with complex amplitude
 * values[j * nx + i] (|value|^2 = its RCS, linear power). Zero pixels cost nothing.
 * With speckle, every amplitude is multiplied by an independent CN(0, 1) sample
 * (kernel::gaussian_noise with speckle_seed, block 0), so E|a|^2 keeps the pixel's RCS.
 */
struct NRSAR_API reflectivity_map {
    unsigned nx = 0;
    unsigned ny = 0;
    double dx = 1.0; //!< pixel spacing along x [m] (> 0)
    double dy = 1.0; //!< pixel spacing along y [m] (> 0)
    double x0 = 0.0; //!< x of pixel column 0 [m]
    double y0 = 0.0; //!< y of pixel row 0 [m]
    std::vector<gr_complex> values; //!< ny * nx amplitudes, row-major (row = y index)
    bool speckle = false;
    std::uint64_t speckle_seed = 0;
    //! Throws std::invalid_argument naming the field, its value and the limit.
    void validate() const;
};

//! Illumination model of the echo generator.
enum class beam_mode {
    WHOLE_BLOCK,      //!< the paper's assumption: every scatterer lit for the whole block
    AZIMUTH,          //!< two-way azimuth pattern sinc^2, eq. (1)
    AZIMUTH_ELEVATION //!< azimuth and elevation patterns, eqs. (1)-(3)
};

/*!
 * \brief The antenna at one instant of a flight: phase centre (SPEC 3 frame) and, for a path
 * with attitude, the body-to-frame rotation (attitude_matrix) that steers the beam.
 */
struct NRSAR_API antenna_pose {
    vec3 position{};
    bool steered = false; //!< the path has attitude: the beam turns with the body
    mat3 rotation{};      //!< body -> frame (when steered)
    //! The pose on path at time t [s] (throws outside a sampled path's span).
    static antenna_pose of(const trajectory& path, double t);
};

/*!
 * \brief Real-aperture antenna of the stripmap SAR, paper eqs. (1)-(3).
 *
 * One-way power pattern sinc^2(D sin(psi) / lambda) (sinc(u) = sin(pi u) / (pi u)),
 * whose half-power width is 0.886 lambda / D, eq. (1); the echo amplitude (two-way)
 * is sinc^2(u_az) [sinc^2(u_el)], with
 *   u_az = D_a (y_q - y_p) / (R lambda)            (sin of the squint angle)
 *   u_el = D_e sin(atan2(x_q, H) - theta_c) / lambda (look angle from nadir vs the boresight)
 * Nulls of the azimuth pattern at u_az = +-1, +-2, ... Scatterers with |u| > cutoff
 * are skipped (the pattern is below (pi cutoff)^-2 there).
 */
struct NRSAR_API antenna_beam {
    beam_mode mode = beam_mode::WHOLE_BLOCK;
    double az_aperture_m = 0.1;             //!< D_a [m] (paper: 0.1)
    double el_aperture_m = 0.1;             //!< D_e [m] (paper: 0.1)
    double el_center_rad = 0.7853981633974483; //!< theta_c, boresight from nadir (paper: pi/4)
    double cutoff = 8.0;                    //!< skip |u| above this (in null widths)

    void validate() const;
    //! eq. (1): 0.886 lambda / D_a [rad].
    double azimuth_beamwidth_rad(const geometry& geo) const;
    //! eq. (1): 0.886 lambda / D_e [rad].
    double elevation_beamwidth_rad(const geometry& geo) const;
    //! eq. (2): azimuth ground coverage 2 H / cos(theta_c) tan(theta_az / 2) [m].
    double azimuth_coverage_m(const geometry& geo) const;
    //! eq. (3): elevation ground coverage H (tan(theta_c + theta_el/2) - tan(theta_c - theta_el/2)) [m].
    double elevation_coverage_m(const geometry& geo) const;
    //! Two-way elevation amplitude of a scatterer at ground range x (1 unless AZIMUTH_ELEVATION).
    double elevation_gain(const geometry& geo, double x_m) const;
    //! Two-way azimuth amplitude for along-track offset dy = y_q - y_p at slant range R.
    double azimuth_gain(const geometry& geo, double dy_m, double range_m) const;
    /*!
     * Two-way amplitude (azimuth x elevation) of a ground scatterer (x_q, y_q, 0) at slant
     * range R seen from pose. Without attitude the antenna keeps the frame's orientation:
     * u_az = D_a (y_q - y_p) / (R lambda), look = atan2(x_q - x_p, z_p) (on the ideal
     * line exactly azimuth_gain() elevation_gain()). With attitude the line of sight l =
     * R^T (q - p) / R is taken into the body: u_az = D_a l_y / lambda, look =
     * atan2(l_x, -l_z), so roll moves the footprint across track, pitch and yaw along it.
     */
    double gain(const geometry& geo,
                const antenna_pose& pose,
                double x_q,
                double y_q,
                double range_m) const;

private:
    double elevation_of_look(const geometry& geo, double look_rad) const;
    double azimuth_of_sine(const geometry& geo, double sin_squint) const;
};

/*!
 * \brief Fast TF echo of an extended scene (maps + point targets), one OFDM symbol at a time.
 *
 * The same echo as kernel::scene_echo, eq. (7) with the exact range (8), for tens of
 * thousands of scatterers:
 *
 *     H[n, m] = sum_k a_k g_k(m) exp(-j 4 pi (fc + n Delta f) R_k(m) / c),   n = 0 .. N-1
 *
 * (g_k = beam amplitude, 1 for WHOLE_BLOCK). Cost per symbol is not K x N: with
 * n = n0 + n', n0 = N / 2, and tau_k = 2 R_k Delta f / c (cycles per subcarrier),
 *
 *     H[n0 + n'] = sum_k b_k exp(-j 2 pi n' tau_k),
 *     b_k = a_k g_k exp(-j 2 pi 2 R_k (fc + n0 Delta f) / c)   (phase in double, eq. 8)
 *
 * is a type-1 non-uniform DFT: every b_k is spread with a Kaiser-Bessel kernel of L taps
 * onto a periodic grid of P >= O N cells in tau (P a 7-smooth size), one forward FFT
 * (gr::fft) gives G[n'] = Phi(n'/P) H[n0 + n'] + aliases, and dividing by the kernel's
 * Fourier transform Phi (exact for the truncated Kaiser-Bessel window) gives H.
 * Cost per symbol: K (sqrt + sincos + L multiply-adds) + P log P + N. L (taps) and O
 * (oversampling) trade run time against error; see docs/scenes.md.
 */
class NRSAR_API extended_scene
{
public:
    /*!
     * \param taps kernel length L (even, 2 .. 32); default 8.
     * \param oversampling O = P / N lower bound (1.25 .. 8); default 2.
     * \param path the true flight path (empty: geo's ideal line; flies_ideal_line): the
     *        range of every scatterer from path.position(m Tsym) in double, and with a
     *        beam its gain from the pose (antenna_beam::gain) per symbol; the elevation
     *        gain is then not folded into the amplitudes.
     * Validates every argument (std::invalid_argument); no scenario check here.
     */
    extended_scene(const numerology& num,
                   const geometry& geo,
                   const scene& points,
                   const std::vector<reflectivity_map>& maps,
                   const antenna_beam& beam = antenna_beam(),
                   unsigned taps = 8,
                   double oversampling = 2.0,
                   const trajectory& path = trajectory());
    extended_scene(extended_scene&&) = default;
    extended_scene& operator=(extended_scene&&) = default;
    extended_scene(const extended_scene&) = delete;
    extended_scene& operator=(const extended_scene&) = delete;

    unsigned num_subcarriers() const { return d_num.num_subcarriers; }
    //! Scatterers kept (non-zero amplitude; elevation cut applied): maps + points.
    std::size_t num_scatterers() const { return d_amp.size(); }
    //! Grid size P of the spreading grid and its FFT.
    unsigned grid_size() const { return d_P; }
    unsigned taps() const { return d_L; }
    //! Sum of |a_k|^2 over all scatterers (no beam): the "total RCS" of the SNR definition.
    double total_power() const { return d_total_power; }
    //! Scatterer k: position and amplitude (after speckle and elevation gain).
    double scatterer_x(std::size_t k) const { return d_x[k]; }
    double scatterer_y(std::size_t k) const { return d_y[k]; }
    std::complex<double> scatterer_amplitude(std::size_t k) const { return d_amp[k]; }
    const antenna_beam& beam() const { return d_beam; }
    double platform_y(std::uint64_t m) const;
    //! The true flight path (empty: the ideal line of the geometry).
    const trajectory& path() const { return d_path; }

    //! h[n] = H[n, m], fast path (the echo of S = 1 without noise).
    void reference(std::uint64_t m, gr_complex* h);
    //! h[n] = H[n, m] by the direct K x N sum in double (slow; benchmarks and tests).
    void reference_exact(std::uint64_t m, gr_complex* h) const;
    /*!
     * y[n] = s[n] H[n, m] + sigma Z[n, m]; non-finite s[n] count as 0.
     * \return the number of non-finite samples of s.
     */
    std::size_t echo(std::uint64_t m,
                     const gr_complex* s,
                     gr_complex* y,
                     gr_complex* h = nullptr,
                     const gaussian_noise* noise = nullptr,
                     float sigma = 0.0f);

private:
    numerology d_num;
    geometry d_geo;
    antenna_beam d_beam;
    trajectory d_path;
    bool d_line; //!< flies geo's ideal line (the bit-identical path)
    unsigned d_L;
    unsigned d_P;
    unsigned d_n0;
    unsigned d_rows; //!< kernel table rows per unit of fractional offset
    double d_total_power = 0.0;
    //! position; (x - x_p)^2 + z_p^2 (x^2 + H^2 on the ideal line, else per symbol)
    std::vector<double> d_x, d_y, d_xh2;
    std::vector<std::complex<double>> d_amp;
    std::vector<gr_complex> d_ampf; //!< d_amp in float for the spreading
    std::vector<float> d_table;       //!< (d_rows + 1) x L kernel weights
    volk::vector<float> d_deapod;     //!< 1 / Phi(n'/P) for n = 0 .. N-1
    volk::vector<gr_complex> d_grid;  //!< P + L cells (the tail wraps onto the head)
    volk::vector<gr_complex> d_h;
    //! Scatterers per pass of reference(): range, reduced phase, grid position, sin, cos.
    static constexpr std::size_t block = 256;
    std::vector<double> d_Rb, d_cycb, d_posb;
    std::vector<float> d_snb, d_csb;
    finite_guard d_guard;
    fft_fwd d_fft;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_EXTENDED_SCENE_H */
