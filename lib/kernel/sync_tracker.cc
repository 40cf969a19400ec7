/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/sync_tracker.h>
#include <algorithm>
#include <complex>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

sync_tracker::sync_tracker(unsigned fft_size,
                           unsigned cp,
                           unsigned symbols_per_slot,
                           std::uint64_t dmrs_offset,
                           unsigned max_early,
                           unsigned miss_limit)
    : d_half(fft_size / 2),
      d_cp(cp),
      d_sps(symbols_per_slot),
      d_sym(std::uint64_t(cp) + fft_size),
      d_slot(std::uint64_t(symbols_per_slot) * (std::uint64_t(cp) + fft_size)),
      d_dmrs(dmrs_offset),
      d_max_early(max_early),
      d_miss_limit(miss_limit),
      d_check_len(3 * std::size_t(cp) + fft_size)
{
    if (fft_size < 4 || fft_size % 2 != 0)
        throw_param("fft_size", fft_size, "must be even and at least 4 (half-symbol repetition)");
    if (symbols_per_slot < 1)
        throw_param("symbols_per_slot", symbols_per_slot, "must be at least 1");
    if (dmrs_offset >= d_slot)
        throw_param("dmrs_offset", dmrs_offset, "must be below the slot length " + std::to_string(d_slot));
    if (max_early > cp)
        throw_param("max_early", max_early, "must be at most cp = " + std::to_string(cp));
    if (miss_limit < 1)
        throw_param("miss_limit", miss_limit, "must be at least 1");
}

std::uint64_t sync_tracker::pad_to_symbol(std::uint64_t g) const
{
    return (d_sym - g % d_sym) % d_sym;
}

sync_tracker::gap_plan sync_tracker::plan_gap(std::uint64_t g, std::uint64_t lost) const
{
    gap_plan p;
    const std::uint64_t end = g + lost;
    p.first_slot = g / d_slot;
    p.resume_slot = (end + d_slot - 1) / d_slot;
    p.pad = pad_to_symbol(g);
    p.drop = p.resume_slot * d_slot - end;
    p.skipped_symbols = p.resume_slot * d_sps - g / d_sym;
    return p;
}

sync_tracker::relock
sync_tracker::relock_at(std::int64_t g, std::uint64_t out_grid, unsigned dmrs_index) const
{
    if (dmrs_index > d_repeats.size())
        throw_param("dmrs_index", dmrs_index, "must be at most the repeats, " + std::to_string(d_repeats.size()));
    const std::int64_t L = std::int64_t(d_slot);
    const std::int64_t first = g - (dmrs_index == 0 ? 0 : d_repeats[dmrs_index - 1]);
    std::int64_t s = ((std::int64_t(d_dmrs) - first) % L + L) % L; // in [0, L)
    if (s > L / 2)
        s -= L;
    const std::int64_t slot = std::max<std::int64_t>((first + s - std::int64_t(d_dmrs)) / L, 0);
    return { s, std::max(std::uint64_t(slot), (out_grid + d_slot - 1) / d_slot), dmrs_index };
}

double sync_tracker::metric_at(const gr_complex* x) const
{
    std::complex<double> p = 0.0;
    double e = 0.0;
    for (std::size_t m = 0; m < d_half; m++) {
        const std::complex<double> a(x[m]), b(x[m + d_half]);
        p += std::conj(a) * b;
        e += std::norm(a) + std::norm(b);
    }
    return e > 0.0 ? std::norm(p) / (0.25 * e * e) : 0.0;
}

unsigned sync_tracker::found_dmrs(const gr_complex* buf,
                                  std::int64_t buf_start,
                                  std::size_t buffered,
                                  std::int64_t symbol_start,
                                  double threshold) const
{
    unsigned j = 0;
    for (; j < d_repeats.size(); j++) {
        bool all = true;
        for (std::size_t k = j; k < d_repeats.size() && all; k++) {
            const std::int64_t at = symbol_start + d_repeats[k] -
                                    (j == 0 ? 0 : d_repeats[j - 1]) + std::int64_t(d_cp / 2) -
                                    buf_start;
            if (at >= 0 && at + 2 * std::int64_t(d_half) <= std::int64_t(buffered))
                all = metric_at(buf + at) >= threshold;
        }
        if (all)
            break;
    }
    return j;
}

std::int64_t sync_tracker::check_start(std::uint64_t slot) const
{
    return std::int64_t(slot * d_slot + d_dmrs) - std::int64_t(d_cp);
}

std::uint64_t sync_tracker::first_checkable_slot(std::uint64_t g) const
{
    // smallest k with k L + dmrs - cp >= g
    const std::int64_t need = std::int64_t(g) - std::int64_t(d_dmrs) + std::int64_t(d_cp);
    if (need <= 0)
        return 0;
    return (std::uint64_t(need) + d_slot - 1) / d_slot;
}

sync_tracker::check sync_tracker::measure(const gr_complex* x) const
{
    // M(d) for d = 0 .. 3 cp (d - cp relative to d0_hat), running sums in double.
    const std::size_t np = 3 * std::size_t(d_cp) + 1;
    const std::size_t H = d_half;
    std::complex<double> p = 0.0;
    double e = 0.0;
    for (std::size_t m = 0; m < H; m++)
        p += std::conj(std::complex<double>(x[m])) * std::complex<double>(x[m + H]);
    for (std::size_t m = 0; m < 2 * H; m++)
        e += std::norm(std::complex<double>(x[m]));
    std::vector<double> M(np);
    for (std::size_t d = 0;; d++) {
        M[d] = e > 0.0 ? std::norm(p) / (0.25 * e * e) : 0.0;
        if (d + 1 == np)
            break;
        const std::complex<double> a(x[d]), b(x[d + H]), c(x[d + 2 * H]);
        p += std::conj(b) * c - std::conj(a) * b;
        e += std::norm(c) - std::norm(a);
    }
    // The plateau: the cp + 1 positions with the largest sum of M (windows start at 0 .. 2 cp).
    double sum = 0.0;
    for (std::size_t d = 0; d <= d_cp; d++)
        sum += M[d];
    double best = sum;
    std::size_t bw = 0;
    for (std::size_t w = 1; w <= 2 * std::size_t(d_cp); w++) {
        sum += M[w + d_cp] - M[w - 1];
        if (sum > best) {
            best = sum;
            bw = w;
        }
    }
    check c;
    for (std::size_t d = bw; d <= bw + d_cp; d++)
        c.mmax = std::max(c.mmax, M[d]);
    c.offset = std::int64_t(bw) - std::int64_t(d_cp);
    return c;
}

bool sync_tracker::score(const check& c, double threshold)
{
    bool miss = !(c.mmax >= threshold);
    if (!miss) {
        // The plateau's start scatters with noise (about 15-19 samples rms at 4-5 dB,
        // sdr20, against max_early 32): the timing tests take the mean offset of the last
        // offset_window slots, which a gap moves by its whole size and noise by 1/sqrt(3).
        d_offsets[d_offset_count++ % offset_window] = c.offset;
        const std::size_t n = std::min(d_offset_count, offset_window);
        std::int64_t sum = 0;
        for (std::size_t i = 0; i < n; i++)
            sum += d_offsets[i];
        const double mean = double(sum) / double(n);
        miss = mean < -double(d_max_early) || mean > double(d_cp / 2);
    }
    if (!miss) {
        d_misses = 0;
        return false;
    }
    d_misses++;
    return d_misses >= d_miss_limit;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
