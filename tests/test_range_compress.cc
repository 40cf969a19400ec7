/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of range_compress (the per-RE filter of eq. 25 and the range compression of
// eq. 29 in one pass) against the two equations evaluated directly in double.

#include <gnuradio/nrsar/kernel/range_compress.h>
#include "test_util.h"
#include <gtest/gtest.h>
#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <vector>

using namespace gr::nrsar;
using cd = std::complex<double>;
using win = gr::fft::window;

namespace {

struct grid {
    std::vector<gr_complex> y, s;
};

// Echo N(0, 1); reference 256-QAM (odd levels -15..15 over sqrt(170)), or QPSK, with every
// `every_empty`-th RE empty.
grid make_grid(std::size_t n, unsigned seed, bool qpsk, std::size_t every_empty)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> level(0, 15);
    grid d;
    d.y = nrsar_test::gaussian_samples(n, seed + 100);
    for (std::size_t i = 0; i < n; i++) {
        gr_complex s;
        if (qpsk)
            s = gr_complex(level(rng) < 8 ? -1.0f : 1.0f, level(rng) < 8 ? -1.0f : 1.0f) /
                std::sqrt(2.0f);
        else
            s = gr_complex(2 * level(rng) - 15, 2 * level(rng) - 15) / std::sqrt(170.0f);
        d.s.push_back(every_empty && i % every_empty == 0 ? gr_complex(0, 0) : s);
    }
    return d;
}

// g(s) of eq. (17), (20), (23); 0 on an empty RE.
cd g_of(filter_type type, cd s, double snr)
{
    const double m = std::norm(s);
    if (type == filter_type::RF)
        return m == 0.0 ? cd(0) : 1.0 / s;
    if (type == filter_type::MF)
        return std::conj(s);
    return std::conj(s) / (m + 1.0 / snr);
}

// eq. (29) of the filtered grid: 1/sqrt(N) sum_n w[n] y[n] g(s[n]) exp(+j 2 pi n k / nfft),
// k = first .. first + count - 1; also the rms of the windowed filtered REs (the scale of
// float rounding).
std::vector<cd> direct(const grid& d,
                       filter_type type,
                       double snr_db,
                       const std::vector<double>& w,
                       unsigned nfft,
                       unsigned first,
                       unsigned count,
                       double& rms)
{
    const std::size_t n = d.y.size();
    const double snr = std::pow(10.0, snr_db / 10.0);
    std::vector<cd> x(n);
    double e = 0.0;
    for (std::size_t i = 0; i < n; i++) {
        x[i] = w[i] * cd(d.y[i]) * g_of(type, cd(d.s[i]), snr);
        e += std::norm(x[i]);
    }
    rms = std::sqrt(e / n);
    std::vector<cd> out(count);
    for (unsigned kk = 0; kk < count; kk++) {
        cd acc = 0;
        for (std::size_t i = 0; i < n; i++)
            acc += x[i] * std::polar(1.0, 2 * M_PI * double(i) * double(first + kk) / nfft);
        out[kk] = acc / std::sqrt(double(n));
    }
    return out;
}

std::vector<double> hann(unsigned n)
{
    std::vector<double> w(n); // written out here: 0.5 - 0.5 cos(2 pi i / (n - 1))
    for (unsigned i = 0; i < n; i++)
        w[i] = 0.5 - 0.5 * std::cos(2 * M_PI * i / (n - 1));
    return w;
}

kernel::range_compress make(unsigned n,
                            filter_type type,
                            double snr_db,
                            unsigned nfft,
                            unsigned first,
                            unsigned count,
                            bool windowed)
{
    return kernel::range_compress(
        kernel::tf_filter(n, type, snr_db, false),
        kernel::range_ifft(n,
                           nfft,
                           windowed ? win::WIN_HANN : win::WIN_RECTANGULAR,
                           win::INVALID_WIN_PARAM,
                           first,
                           count));
}

// Float rounding of an N-term sum of terms of size rms: a few eps sqrt(N) log2(nfft) rms;
// 5e-6 sqrt(N) rms is above it for every size here and far below any filter or window error.
void expect_direct(filter_type type, bool qpsk, std::size_t every_empty, bool windowed)
{
    const unsigned n = 997, nfft = 1008, first = 40, count = 300; // odd N: the loop tails
    const double snr_db = -10.0;
    const auto d = make_grid(n, 11, qpsk, every_empty);
    auto k = make(n, type, snr_db, nfft, first, count, windowed);
    std::vector<gr_complex> out(count);
    EXPECT_EQ(k.process(d.y.data(), d.s.data(), out.data()), 0u);
    double rms = 0.0;
    const auto ref =
        direct(d, type, snr_db, windowed ? hann(n) : std::vector<double>(n, 1.0), nfft,
               first, count, rms);
    for (unsigned i = 0; i < count; i++)
        EXPECT_NEAR(std::abs(cd(out[i]) - ref[i]), 0.0, 5e-6 * std::sqrt(double(n)) * rms)
            << "bin " << first + i;
    EXPECT_EQ(k.filter().empty_re_count(), every_empty ? (n + every_empty - 1) / every_empty : 0);
}

} // namespace

TEST(RangeCompress, WienerWindowedPaddedCroppedMatchesDirect)
{
    expect_direct(filter_type::WF, false, 0, true);
}
TEST(RangeCompress, ReciprocalWithEmptyREsMatchesDirect)
{
    expect_direct(filter_type::RF, false, 5, true);
}
TEST(RangeCompress, MatchedUnwindowedMatchesDirect)
{
    expect_direct(filter_type::MF, false, 7, false);
}
TEST(RangeCompress, ConstantModulusShortcutMatchesDirect)
{
    // QPSK takes tf_filter's constant-modulus path; the window is applied after it.
    for (auto t : { filter_type::RF, filter_type::WF })
        expect_direct(t, true, 3, true);
}

TEST(RangeCompress, EqualsTheSeparateKernelsAtPaperSize)
{
    // tf_filter then range_ifft, as the unfused blocks run them: the same profile within
    // float rounding (the two FFTW plans may differ).
    const unsigned n = 3333, nfft = 3360, first = 100, count = 90;
    const auto d = make_grid(n, 5, false, 0);
    auto fused = make(n, filter_type::WF, -20.0, nfft, first, count, true);
    kernel::tf_filter filter(n, filter_type::WF, -20.0, false);
    kernel::range_ifft ifft(n, nfft, win::WIN_HANN, win::INVALID_WIN_PARAM, first, count);
    std::vector<gr_complex> filtered(n), a(count), b(count);
    for (int rep = 0; rep < 2; rep++) { // the padding stays zero from call to call
        fused.process(d.y.data(), d.s.data(), a.data());
        filter.process(d.y.data(), d.s.data(), filtered.data());
        ifft.execute(filtered.data(), b.data());
        double peak = 0.0, err = 0.0;
        for (unsigned i = 0; i < count; i++) {
            peak = std::max(peak, double(std::abs(b[i])));
            err = std::max(err, double(std::abs(a[i] - b[i])));
        }
        EXPECT_LT(err, 1e-5 * peak);
    }
}

TEST(RangeCompress, NonFiniteInputsAreZeroedAndCounted)
{
    const unsigned n = 64, nfft = 80, first = 0, count = 80;
    auto d = make_grid(n, 3, false, 0);
    d.y[5] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
    d.s[30] = gr_complex(0.0f, std::numeric_limits<float>::infinity());
    auto k = make(n, filter_type::WF, 0.0, nfft, first, count, true);
    std::vector<gr_complex> out(count);
    EXPECT_EQ(k.process(d.y.data(), d.s.data(), out.data()), 2u);
    // the profile of the grid with both REs zeroed (a zeroed reference is an empty RE)
    d.y[5] = gr_complex(0, 0);
    d.s[30] = gr_complex(0, 0);
    double rms = 0.0;
    const auto ref = direct(d, filter_type::WF, 0.0, hann(n), nfft, first, count, rms);
    for (unsigned i = 0; i < count; i++)
        EXPECT_NEAR(std::abs(cd(out[i]) - ref[i]), 0.0, 5e-6 * std::sqrt(double(n)) * rms);
    EXPECT_EQ(k.filter().nonfinite_count(), 2u);
}

TEST(RangeCompress, RejectsMismatchedLengths)
{
    const auto msg = nrsar_test::error_of([] {
        kernel::range_compress(kernel::tf_filter(100, filter_type::MF, 0.0, false),
                               kernel::range_ifft(101, 128));
    });
    EXPECT_NE(msg.find("vlen = 100"), std::string::npos) << msg;
    EXPECT_NE(msg.find("101"), std::string::npos) << msg;
}
