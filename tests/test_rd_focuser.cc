/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of the range-Doppler focuser: the sinc interpolator against the direct
// windowed-sinc sum and against a known band-limited signal, and the focus of a synthetic
// point target (exact range history) at its true position with the predicted peak.

#include <gnuradio/nrsar/kernel/fft_size.h>
#include <gnuradio/nrsar/kernel/rd_focuser.h>
#include <gnuradio/nrsar/kernel/sinc_interpolator.h>
#include <gnuradio/nrsar/params.h>
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

using gr::nrsar::doppler_band;
using gr::nrsar::focuser_config;
using gr::nrsar::kernel::rd_block;
using gr::nrsar::kernel::rd_focuser;
using gr::nrsar::kernel::sinc_interpolator;
using cd = std::complex<double>;

TEST(sinc_interpolator, table_matches_direct_sum)
{
    sinc_interpolator interp(16, gr::fft::window::WIN_KAISER, 6.0, 1024);
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    const int n = 64;
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    std::uniform_real_distribution<double> u(-2.0, n + 1.0);
    for (int t = 0; t < 500; ++t) {
        const double pos = u(rng);
        // Direct: sum_j x[i + j] h(j - mu), normalised to unit DC gain, in double.
        const double fl = std::floor(pos);
        const double mu = pos - fl;
        cd acc(0.0, 0.0);
        double norm = 0.0;
        for (int j = -7; j <= 8; ++j) {
            const double h = interp.kernel(j - mu);
            norm += h;
            const int idx = static_cast<int>(fl) + j;
            if (idx >= 0 && idx < n)
                acc += cd(x[idx].real(), x[idx].imag()) * h;
        }
        acc /= norm;
        const gr_complex got = interp.at(x.data(), n, pos);
        // Nearest of 1024 phases: shift error <= 1/2048 sample.
        EXPECT_LT(std::abs(cd(got.real(), got.imag()) - acc), 5e-3) << "pos " << pos;
    }
}

TEST(sinc_interpolator, reproduces_band_limited_signal)
{
    // A complex exponential at 0.35 cycles/sample, interior samples: the 16-tap Kaiser(6)
    // kernel interpolates it to better than -40 dB.
    sinc_interpolator interp(16, gr::fft::window::WIN_KAISER, 6.0, 4096);
    const int n = 128;
    const double f = 0.35;
    std::vector<gr_complex> x(n);
    for (int k = 0; k < n; ++k)
        x[k] = gr_complex(std::cos(2 * M_PI * f * k), std::sin(2 * M_PI * f * k));
    std::vector<float> shift(n);
    std::vector<gr_complex> y(n);
    for (int k = 0; k < n; ++k)
        shift[k] = static_cast<float>(0.37 + 0.01 * k);
    interp.resample(x.data(), n, shift.data(), y.data());
    double err = 0.0, cnt = 0.0;
    for (int k = 10; k < n - 12; ++k) {
        const double p = k + static_cast<double>(shift[k]);
        err += std::norm(cd(y[k].real(), y[k].imag()) - std::polar(1.0, 2 * M_PI * f * p));
        cnt += 1.0;
    }
    EXPECT_LT(10 * std::log10(err / cnt), -40.0);
    // A constant is reproduced exactly (unit DC gain of every phase).
    std::vector<gr_complex> c(n, gr_complex(1.0f, -2.0f));
    interp.resample(c.data(), n, shift.data(), y.data());
    EXPECT_NEAR(y[40].real(), 1.0f, 1e-5f);
    EXPECT_NEAR(y[40].imag(), -2.0f, 1e-5f);
}

TEST(sinc_interpolator, rejects_bad_taps)
{
    EXPECT_THROW(sinc_interpolator(7), std::invalid_argument);
    EXPECT_THROW(sinc_interpolator(0), std::invalid_argument);
    EXPECT_THROW(sinc_interpolator(16, gr::fft::window::WIN_FLATTOP), std::invalid_argument);
}

namespace {
// Exact range-compressed echo of a unit point target, eqs. (8), (29): for pulse m,
// r_m(k) = sum_{n<N} exp(j 2 pi n (k - k_q,m) / nfft) / sqrt(N) exp(-j 4 pi R_q(m) / lambda),
// k_q,m = (R_q(m) - r_first) / rho, rho = c / (2 nfft Delta f).
// Paper-like range (R0 = 1000 m) and carrier; a 200 m aperture centred on the target gives
// 3.3 range bins of migration at the band edges (+-116 Hz), at PRF 400 Hz.
struct scenario {
    unsigned n_sub = 32, nfft = 64, K = 64, M = 1600;
    double T = 2.5e-3, v = 50.0, lambda = gr::nrsar::speed_of_light / 3.5e9;
    double rho = 1.5, r_first = 955.0;
    double x = 800.0, h = 600.0, y = 100.0; // target; platform at y_p = v t
};

std::vector<gr_complex> echo(const scenario& s)
{
    std::vector<gr_complex> out(static_cast<size_t>(s.M) * s.K);
    for (unsigned m = 0; m < s.M; ++m) {
        const double dy = s.v * m * s.T - s.y;
        const double r = std::sqrt(s.x * s.x + s.h * s.h + dy * dy);
        const double kq = (r - s.r_first) / s.rho;
        const cd carrier = std::polar(1.0, -4 * M_PI * std::fmod(r / s.lambda, 1.0));
        for (unsigned k = 0; k < s.K; ++k) {
            cd acc(0.0, 0.0);
            for (unsigned n = 0; n < s.n_sub; ++n)
                acc += std::polar(1.0, 2 * M_PI * n * (k - kq) / s.nfft);
            const cd val = acc / std::sqrt(double(s.n_sub)) * carrier;
            out[static_cast<size_t>(m) * s.K + k] = gr_complex(val.real(), val.imag());
        }
    }
    return out;
}

// Range-major copy by a direct loop (independent of kernel::transpose): bin k's lines at
// k * stride.
std::vector<gr_complex> range_major(const std::vector<gr_complex>& in, const scenario& s, size_t stride)
{
    std::vector<gr_complex> rm(stride * s.K);
    for (unsigned m = 0; m < s.M; ++m)
        for (unsigned k = 0; k < s.K; ++k)
            rm[k * stride + m] = in[static_cast<size_t>(m) * s.K + k];
    return rm;
}

rd_block block_of(const scenario& s)
{
    rd_block b;
    b.num_range_bins = s.K;
    b.num_lines = s.M;
    b.pulse_interval_s = s.T;
    b.velocity_mps = s.v;
    b.wavelength_m = s.lambda;
    b.first_range_m = s.r_first;
    b.range_bin_m = s.rho;
    // Doppler band of the target over the block, 2 v (y - y_p) / (lambda R), plus margin.
    auto fd = [&](double yp) {
        const double dy = s.y - yp;
        return 2 * s.v * dy / (s.lambda * std::sqrt(s.x * s.x + s.h * s.h + dy * dy));
    };
    b.band_lo_hz = fd(s.v * (s.M - 1) * s.T) - 20.0;
    b.band_hi_hz = fd(0.0) + 20.0;
    b.range_centre_cycles = (s.n_sub - 1) / (2.0 * s.nfft);
    return b;
}
} // namespace

TEST(rd_focuser, focuses_target_at_true_position)
{
    scenario s;
    const auto in = echo(s);
    focuser_config cfg;
    cfg.fast_fft_size = false;
    rd_focuser f(cfg, block_of(s));
    std::vector<gr_complex> img(in.size());
    f.focus(in.data(), img.data());

    size_t best = 0;
    for (size_t i = 0; i < img.size(); ++i)
        if (std::abs(img[i]) > std::abs(img[best]))
            best = i;
    const double m_peak = double(best / s.K), k_peak = double(best % s.K);
    const double r0 = std::sqrt(s.x * s.x + s.h * s.h);
    const double k_true = (r0 - s.r_first) / s.rho;
    const double m_true = s.y / (s.v * s.T);
    // Resolution cells: range nfft / N bins, azimuth PRF / B_t lines.
    const double fd0 = 2 * s.v * s.y / (s.lambda * std::hypot(r0, s.y));
    const double b_t = 2 * fd0; // symmetric aperture
    EXPECT_LE(std::abs(k_peak - k_true), 0.25 * s.nfft / s.n_sub + 0.5);
    EXPECT_LE(std::abs(m_peak - m_true), 0.25 / (b_t * s.T) + 0.5);
    EXPECT_TRUE(f.rcmc_applied());
    EXPECT_GT(f.max_migration_bins(), 3.0);
    // Unitary scaling: peak = sqrt(N) sqrt(M_t B_t T) (stationary phase; the target sits
    // on a range bin), within 0.5 dB.
    const double predicted = std::sqrt(double(s.n_sub)) * std::sqrt(s.M * b_t * s.T);
    const double got = std::abs(img[best]);
    EXPECT_NEAR(20 * std::log10(got / predicted), 0.0, 0.5);

    // Without RCMC the migrated energy spreads over range: a lower peak.
    focuser_config no_rcmc = cfg;
    no_rcmc.rcmc = false;
    rd_focuser g(no_rcmc, block_of(s));
    std::vector<gr_complex> img2(in.size());
    g.focus(in.data(), img2.data());
    double peak2 = 0.0;
    for (const auto& v : img2)
        peak2 = std::max(peak2, double(std::abs(v)));
    EXPECT_LT(peak2, 0.8 * got);
}

TEST(rd_focuser, band_restriction_keeps_peak)
{
    scenario s;
    const auto in = echo(s);
    focuser_config scene_cfg;
    focuser_config full_cfg;
    full_cfg.band = doppler_band::FULL;
    rd_focuser a(scene_cfg, block_of(s));
    rd_focuser b(full_cfg, block_of(s));
    std::vector<gr_complex> ia(in.size()), ib(in.size());
    a.focus(in.data(), ia.data());
    b.focus(in.data(), ib.data());
    double pa = 0.0, pb = 0.0;
    for (size_t i = 0; i < ia.size(); ++i) {
        pa = std::max(pa, double(std::abs(ia[i])));
        pb = std::max(pb, double(std::abs(ib[i])));
    }
    EXPECT_NEAR(20 * std::log10(pa / pb), 0.0, 0.1);
    EXPECT_LT(a.band_bins(), b.band_bins());
    EXPECT_EQ(b.band_bins(), b.fft_size());
}

TEST(rd_focuser, configured_band_bins_is_the_kernels)
{
    // What sizes memory before any kernel is built (aperture_focuser::band_bins, the
    // Python memory estimate) against the kernel's own count, and against the integers j in
    // [lo / df, hi / df], df = 1 / (nfft T), one bin each (at least one: the bin nearest to
    // the centre; every bin for FULL or a band of the pulse rate or more). The Python copy
    // it replaces, min(nfft, ceil((hi - lo) nfft T) + 1), said 2 for the two narrow bands
    // and one bin more than the kernel for most others. At 1600 lines df = 0.25 Hz.
    scenario s;
    s.K = 8; // the band does not depend on the range bins
    struct band_case {
        double lo, hi;
        doppler_band band;
        bool fast;
        unsigned lines;
        bool on_bins; // edges on bin frequencies: rounding decides, the kernel's count only
    };
    const band_case cases[] = {
        { -96.1, 117.3, doppler_band::SCENE, true, 1600, false },    // 854 bins
        { 190.1, 230.3, doppler_band::SCENE, true, 1600, false },    // across PRF / 2: 161
        { 10.0, 10.05, doppler_band::SCENE, true, 1600, false },     // inside one bin: 1
        { 10.01, 10.2, doppler_band::SCENE, true, 1600, false },     // between bins: 1
        { -25.0, 25.0, doppler_band::SCENE, true, 1600, true },
        { -96.1, 117.3, doppler_band::FULL, true, 1600, false },     // 1600
        { -96.1, 117.3, doppler_band::ESTIMATE, true, 1600, false }, // the fallback: 854
        { -300.0, 150.0, doppler_band::SCENE, true, 1600, false },   // over the PRF: 1600
        { -96.1, 117.3, doppler_band::SCENE, false, 1601, false },   // nfft = 1601
        { -96.1, 117.3, doppler_band::SCENE, true, 1601, false },    // nfft 7-smooth > 1601
    };
    for (const auto& c : cases) {
        focuser_config cfg;
        cfg.band = c.band;
        cfg.fast_fft_size = c.fast;
        s.M = c.lines;
        rd_block blk = block_of(s);
        blk.band_lo_hz = c.lo;
        blk.band_hi_hz = c.hi;
        const unsigned got = rd_focuser::configured_band_bins(cfg, blk);
        const rd_focuser kernel(cfg, blk);
        EXPECT_EQ(got, kernel.band_bins()) << c.lo << " " << c.hi << " " << c.lines;
        const unsigned nfft = kernel.fft_size();
        EXPECT_EQ(nfft, c.fast ? gr::nrsar::kernel::fast_fft_size(c.lines) : c.lines);
        if (c.on_bins)
            continue;
        const double df = 1.0 / (nfft * s.T);
        const bool full = c.band == doppler_band::FULL || c.hi - c.lo >= 1.0 / s.T;
        const long inside = static_cast<long>(std::floor(c.hi / df) - std::ceil(c.lo / df)) + 1;
        EXPECT_EQ(got, full ? nfft : static_cast<unsigned>(std::max(1L, inside)))
            << c.lo << " " << c.hi << " " << c.lines;
    }
}

TEST(rd_focuser, range_major_input_gives_the_same_image)
{
    scenario s;
    s.M = 400;
    s.y = 10.0;
    const auto in = echo(s);
    focuser_config cfg;
    rd_focuser f(cfg, block_of(s));
    std::vector<gr_complex> a(in.size()), b(in.size()), rm(in.size());
    f.focus(in.data(), a.data());
    // Range-major copy by a direct loop (independent of kernel::transpose), row stride M + 3.
    const size_t stride = s.M + 3;
    rm = range_major(in, s, stride);
    f.focus_range_major(rm.data(), stride, b.data(), 0, s.M);
    for (size_t i = 0; i < a.size(); ++i)
        ASSERT_EQ(a[i], b[i]) << i;
    // A sub-range of output lines is the same sub-range of the full image.
    std::vector<gr_complex> c(static_cast<size_t>(50) * s.K);
    f.focus_range_major(rm.data(), stride, c.data(), 100, 50);
    for (size_t i = 0; i < c.size(); ++i)
        ASSERT_EQ(c[i], a[100 * s.K + i]) << i;
    EXPECT_THROW(f.focus_range_major(rm.data(), stride, c.data(), 380, 50),
                 std::invalid_argument);
}

TEST(rd_focuser, line_shift_rotates_the_output)
{
    scenario s;
    s.M = 400;
    s.y = 10.0;
    const auto in = echo(s);
    focuser_config cfg;
    cfg.fast_fft_size = false; // N = M: the rotation is exactly circular over the block
    rd_block b0 = block_of(s);
    rd_block b1 = b0;
    b1.line_shift = 137;
    rd_focuser f0(cfg, b0), f1(cfg, b1);
    std::vector<gr_complex> a(in.size()), b(in.size());
    f0.focus(in.data(), a.data());
    f1.focus(in.data(), b.data());
    double err = 0.0, ref = 0.0;
    for (unsigned m = 0; m < s.M; ++m)
        for (unsigned k = 0; k < s.K; ++k) {
            const gr_complex x = a[((m + 137) % s.M) * s.K + k];
            err += std::norm(b[m * s.K + k] - x);
            ref += std::norm(x);
        }
    EXPECT_LT(10 * std::log10(err / ref), -100.0);
}

TEST(rd_focuser, estimated_band_covers_the_target)
{
    scenario s;
    s.M = 400;
    s.y = 10.0;
    const auto in = echo(s);
    focuser_config cfg;
    cfg.band = doppler_band::ESTIMATE;
    rd_block b = block_of(s);
    rd_focuser f(cfg, b);
    std::vector<gr_complex> img(in.size());
    f.focus(in.data(), img.data());
    auto fd = [&](double yp) {
        const double dy = s.y - yp;
        return 2 * s.v * dy / (s.lambda * std::sqrt(s.x * s.x + s.h * s.h + dy * dy));
    };
    const double lo = fd(s.v * (s.M - 1) * s.T), hi = fd(0.0);
    EXPECT_LE(f.band_lo_hz(), lo);
    EXPECT_GE(f.band_hi_hz(), hi);
    // Conservative: the -20 dB edges of a truncated chirp spectrum, plus the margin.
    EXPECT_LT(f.band_hi_hz() - f.band_lo_hz(), 2.0 * (hi - lo));
}

TEST(rd_focuser, transpose_matches_direct_loop)
{
    const unsigned rows = 77, cols = 45;
    std::vector<gr_complex> src(rows * cols), dst(static_cast<size_t>(cols) * (rows + 5));
    for (unsigned i = 0; i < src.size(); ++i)
        src[i] = gr_complex(float(i), -float(i));
    gr::nrsar::kernel::transpose(src.data(), cols, dst.data(), rows + 5, rows, cols);
    for (unsigned r = 0; r < rows; ++r)
        for (unsigned c = 0; c < cols; ++c)
            ASSERT_EQ(dst[c * (rows + 5) + r], src[r * cols + c]);
}


TEST(rd_focuser, range_doppler_map_output)
{
    scenario s;
    s.M = 800;
    s.y = 20.0;
    const auto in = echo(s);
    focuser_config cfg;
    cfg.rcmc_skip_below_bins = 0.0;
    rd_focuser f(cfg, block_of(s));
    std::vector<gr_complex> a(in.size()), b(in.size());
    f.focus(in.data(), a.data());
    // Range-major copy, as the block stores it.
    const auto rm = range_major(in, s, s.M);
    const unsigned B = f.band_bins();
    std::vector<gr_complex> map(static_cast<size_t>(B) * s.K);
    f.focus_range_major(rm.data(), s.M, b.data(), 0, s.M, map.data());
    // The map costs nothing in the image: identical output.
    for (size_t i = 0; i < a.size(); ++i)
        ASSERT_EQ(a[i], b[i]) << i;
    ASSERT_TRUE(f.rcmc_applied());
    // After RCMC the target is a straight line at its closest-approach range bin in every
    // Doppler line that holds its energy (before RCMC it would migrate by up to
    // max_migration_bins()).
    const double k_true = (std::sqrt(s.x * s.x + s.h * s.h) - s.r_first) / s.rho;
    double peak = 0.0;
    for (const auto& v : map)
        peak = std::max(peak, double(std::abs(v)));
    unsigned strong = 0;
    for (unsigned r = 0; r < B; ++r) {
        unsigned kb = 0;
        for (unsigned k = 1; k < s.K; ++k)
            if (std::abs(map[r * s.K + k]) > std::abs(map[r * s.K + kb]))
                kb = k;
        if (std::abs(map[r * s.K + kb]) < 0.5 * peak)
            continue;
        ++strong;
        EXPECT_LE(std::abs(kb - k_true), 1.0) << "Doppler line " << r;
    }
    EXPECT_GT(strong, B / 4);

    // Without RCMC the map is the azimuth DFT itself, lines in ascending Doppler: checked
    // against a direct double-precision DFT at a few cells.
    focuser_config plain = cfg;
    plain.rcmc = false;
    rd_focuser g(plain, block_of(s));
    std::vector<gr_complex> map2(static_cast<size_t>(g.band_bins()) * s.K);
    g.focus_range_major(rm.data(), s.M, b.data(), 0, s.M, map2.data());
    const double prf = 1.0 / s.T, df = prf / g.fft_size();
    for (unsigned r : { 0u, g.band_bins() / 2, g.band_bins() - 1 }) {
        const double f_hz = g.rd_doppler_first_hz() + r * df;
        for (unsigned k : { 10u, static_cast<unsigned>(k_true) }) {
            cd acc(0.0, 0.0);
            for (unsigned m = 0; m < s.M; ++m)
                acc += cd(in[static_cast<size_t>(m) * s.K + k]) *
                       std::polar(1.0, -2 * M_PI * f_hz * m * s.T);
            const double got = std::abs(map2[static_cast<size_t>(r) * s.K + k]);
            EXPECT_NEAR(got, std::abs(acc), 1e-3 * std::abs(acc) + 1e-3) << r << " " << k;
        }
    }
}
