/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Kernel tests of range compression, eq. (29), against a direct O(N^2) DFT in double.

#include <gnuradio/nrsar/kernel/range_ifft.h>
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

// out[k'] = 1/sqrt(N) sum_n w[n] x[n] exp(+j 2 pi n (first + k') / nfft)
std::vector<cd> direct(const std::vector<gr_complex>& x,
                       const std::vector<double>& w,
                       unsigned nfft,
                       unsigned first,
                       unsigned count)
{
    const std::size_t n = x.size();
    std::vector<cd> out(count);
    for (unsigned kk = 0; kk < count; kk++) {
        cd acc = 0;
        for (std::size_t i = 0; i < n; i++)
            acc += w[i] * cd(x[i]) *
                   std::polar(1.0, 2 * M_PI * double(i) * double(first + kk) / nfft);
        out[kk] = acc / std::sqrt(double(n));
    }
    return out;
}

void expect_direct(unsigned n, unsigned nfft, unsigned first, unsigned count, bool hann)
{
    const auto x = nrsar_test::gaussian_samples(n, n + nfft);
    std::vector<double> w(n, 1.0);
    if (hann) // Hann written out here: 0.5 - 0.5 cos(2 pi i / (n - 1))
        for (unsigned i = 0; i < n; i++)
            w[i] = 0.5 - 0.5 * std::cos(2 * M_PI * i / (n - 1));
    kernel::range_ifft k(
        n, nfft, hann ? win::WIN_HANN : win::WIN_RECTANGULAR, win::INVALID_WIN_PARAM, first, count);
    ASSERT_EQ(k.num_bins(), count);
    std::vector<gr_complex> out(count);
    k.execute(x.data(), out.data());
    const auto ref = direct(x, w, nfft, first, count);
    for (unsigned i = 0; i < count; i++)
        EXPECT_NEAR(std::abs(cd(out[i]) - ref[i]), 0.0, 2e-5 * std::sqrt(double(n)))
            << "bin " << first + i;
}

} // namespace

TEST(RangeIfft, MatchesDirectDftNoPadding) { expect_direct(60, 60, 0, 60, false); }
TEST(RangeIfft, MatchesDirectDftOddPrimeSize) { expect_direct(101, 101, 0, 101, false); }
TEST(RangeIfft, MatchesDirectDftPaddedCropped) { expect_direct(50, 64, 5, 20, false); }
TEST(RangeIfft, MatchesDirectDftWindowedPaddedCropped) { expect_direct(50, 75, 10, 30, true); }

TEST(RangeIfft, NonFiniteSamplesAreZeroedAndCounted)
{
    // The window pass carries the finite check: a NaN and an Inf count as zeros, and the
    // profile is the direct DFT of the input with them zeroed.
    const unsigned n = 50, nfft = 75, first = 10, count = 30;
    auto x = nrsar_test::gaussian_samples(n, 11);
    x[7] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 1.0f);
    x[42] = gr_complex(0.0f, -std::numeric_limits<float>::infinity());
    kernel::range_ifft k(n, nfft, win::WIN_RECTANGULAR, win::INVALID_WIN_PARAM, first, count);
    std::vector<gr_complex> out(count);
    EXPECT_EQ(k.execute(x.data(), out.data()), 2u);
    x[7] = x[42] = gr_complex(0.0f, 0.0f);
    const auto ref = direct(x, std::vector<double>(n, 1.0), nfft, first, count);
    for (unsigned i = 0; i < count; i++)
        EXPECT_NEAR(std::abs(cd(out[i]) - ref[i]), 0.0, 2e-5 * std::sqrt(double(n)))
            << "bin " << first + i;
    // the next, finite symbol is not affected
    EXPECT_EQ(k.execute(x.data(), out.data()), 0u);
}

TEST(RangeIfft, PaperSizeMatchesDirectDftAcrossCalls)
{
    // The paper's 3333 subcarriers padded to 3360, Hann, a 56-bin crop: the window pass
    // runs 416 eight-sample AVX2 steps and a 5-sample scalar tail; a NaN in each is zeroed.
    // Every call reads only its own symbol (the padding stays zero, the taps unchanged),
    // so a symbol between two calls on the same input leaves the output bit for bit.
    const unsigned n = 3333, nfft = 3360, first = 700, count = 56;
    auto x = nrsar_test::gaussian_samples(n, 5);
    x[5] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
    x[n - 1] = gr_complex(1.0f, std::numeric_limits<float>::quiet_NaN());
    std::vector<double> w(n);
    for (unsigned i = 0; i < n; i++)
        w[i] = 0.5 - 0.5 * std::cos(2 * M_PI * i / (n - 1));
    kernel::range_ifft k(n, nfft, win::WIN_HANN, win::INVALID_WIN_PARAM, first, count);
    std::vector<gr_complex> out(count), other(count), again(count);
    EXPECT_EQ(k.execute(x.data(), out.data()), 2u);
    const auto y = nrsar_test::gaussian_samples(n, 6);
    EXPECT_EQ(k.execute(y.data(), other.data()), 0u);
    EXPECT_EQ(k.execute(x.data(), again.data()), 2u);
    x[5] = x[n - 1] = gr_complex(0.0f, 0.0f);
    const auto ref = direct(x, w, nfft, first, count);
    for (unsigned i = 0; i < count; i++) {
        // bins of RMS about 0.9 (unit-variance samples, mean(w^2) = 3/8): float rounding
        EXPECT_NEAR(std::abs(cd(out[i]) - ref[i]), 0.0, 2e-6) << "bin " << first + i;
        EXPECT_EQ(out[i], again[i]) << "bin " << first + i;
    }
}

TEST(RangeIfft, ZeroMeansNoPaddingAndAllBins)
{
    kernel::range_ifft k(48, 0);
    EXPECT_EQ(k.fft_size(), 48u);
    EXPECT_EQ(k.first_bin(), 0u);
    EXPECT_EQ(k.num_bins(), 48u);
}

TEST(RangeIfft, FullBandTargetPeakIndependentOfPadding)
{
    // A unit-amplitude full-band target on bin 7 of N, x[n] = exp(-j 2 pi n 7 / N) (the
    // delay phase of eq. (27)), is bin 7 P of the transform padded to nfft = N P.
    const unsigned n = 40;
    std::vector<gr_complex> x(n);
    for (unsigned i = 0; i < n; i++)
        x[i] = gr_complex(std::polar(1.0, -2 * M_PI * i * 7.0 / n));
    for (unsigned pad : { 1u, 2u, 4u }) {
        for (auto w : { win::WIN_RECTANGULAR, win::WIN_HAMMING }) {
            kernel::range_ifft k(n, n * pad, w);
            std::vector<gr_complex> out(k.num_bins());
            k.execute(x.data(), out.data());
            const unsigned peak = 7 * pad;
            EXPECT_NEAR(std::abs(out[peak]), std::sqrt(double(n)) * k.coherent_gain(), 1e-4);
            for (unsigned b = 0; b < k.num_bins(); b++)
                EXPECT_LE(std::abs(out[b]), std::abs(out[peak]) + 1e-4);
        }
    }
}

TEST(RangeIfft, WindowTapsAreGnuRadioWindow)
{
    kernel::range_ifft k(33, 64, win::WIN_BLACKMAN);
    const auto ref = win::blackman(33);
    const auto taps = k.window_taps();
    ASSERT_EQ(taps.size(), ref.size());
    double sum = 0;
    for (std::size_t i = 0; i < ref.size(); i++) {
        EXPECT_NEAR(taps[i], ref[i], 1e-6);
        sum += ref[i];
    }
    EXPECT_NEAR(k.coherent_gain(), sum / 33, 1e-9);
    k.set_window(win::WIN_RECTANGULAR, win::INVALID_WIN_PARAM);
    EXPECT_NEAR(k.coherent_gain(), 1.0, 1e-12);
}

TEST(RangeIfft, FastFftSizeIsSmallestSevenSmooth)
{
    auto smooth = [](unsigned m) {
        for (unsigned p : { 2u, 3u, 5u, 7u })
            while (m % p == 0)
                m /= p;
        return m == 1;
    };
    EXPECT_EQ(kernel::fast_fft_size(3333), 3360u); // 2^5 3 5 7
    EXPECT_EQ(kernel::fast_fft_size(4096), 4096u);
    EXPECT_EQ(kernel::fast_fft_size(1), 1u);
    EXPECT_EQ(kernel::fast_fft_size(48000), 48000u); // the paper's aperture: 2^7 3 5^3
    for (unsigned n = 2; n < 3000; n += 37) {
        const unsigned f = kernel::fast_fft_size(n);
        EXPECT_TRUE(smooth(f));
        EXPECT_GE(f, n);
        for (unsigned m = n; m < f; m++)
            EXPECT_FALSE(smooth(m)) << m;
    }
    EXPECT_EQ(kernel::pow2_fft_size(3333), 4096u);
}

TEST(RangeIfft, CropBinsCeilFloor)
{
    // bins at 0, 1.5, 3.0, 4.5, ... m
    auto b = kernel::range_ifft::crop_bins(1.5, 100, 3.0, 9.0);
    EXPECT_EQ(b.first, 2u); // 3.0 m is bin 2 itself
    EXPECT_EQ(b.count, 5u); // bins 2..6 (9.0 m = bin 6)
    b = kernel::range_ifft::crop_bins(1.5, 100, 3.1, 8.9);
    EXPECT_EQ(b.first, 3u);
    EXPECT_EQ(b.count, 3u); // bins 3..5
    b = kernel::range_ifft::crop_bins(1.5, 100, 10.0, 0.0);
    EXPECT_EQ(b.first, 7u);
    EXPECT_EQ(b.count, 93u); // up to bin 99
    b = kernel::range_ifft::crop_bins(1.5, 100, 3.1, 3.2);
    EXPECT_EQ(b.count, 0u);
    b = kernel::range_ifft::crop_bins(1.5, 100, 0.0, 1e6);
    EXPECT_EQ(b.count, 100u);
}

TEST(RangeIfft, RejectsBadSizes)
{
    EXPECT_THROW(kernel::range_ifft(64, 32), std::invalid_argument);
    EXPECT_THROW(kernel::range_ifft(64, 64, win::WIN_RECTANGULAR, -1, 64, 1), std::invalid_argument);
    EXPECT_THROW(kernel::range_ifft(64, 64, win::WIN_RECTANGULAR, -1, 60, 5), std::invalid_argument);
}
