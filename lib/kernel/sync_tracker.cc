/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/dmrs.h>
#include <gnuradio/nrsar/kernel/sync_tracker.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

dmrs_matcher::dmrs_matcher(const numerology& num, const dmrs_config& dmrs, double false_alarm)
    : d_fft(num.fft_size),
      d_cp(num.cp_samples),
      d_symbols(dmrs.symbols.size()),
      d_slots(num.slots_per_frame),
      d_demod(num.num_subcarriers, num.fft_size, 0, num.dc_subcarrier(), 0),
      d_y(num.num_subcarriers)
{
    if (!(false_alarm > 0.0 && false_alarm < 1.0))
        throw_param("false_alarm", false_alarm, "must be in (0, 1)");
    const unsigned n = dmrs_count(num.num_subcarriers);
    if (n < 2)
        throw_param("num_subcarriers", num.num_subcarriers, "must be at least 3 (two DMRS REs)");
    // P(rho > t) = exp(-t^2 n^2 / (n - 1)) (class comment)
    d_threshold = std::sqrt(-std::log(false_alarm) * double(n - 1)) / double(n);
    for (unsigned s = 0; s < d_slots; s++)
        for (unsigned l : dmrs.symbols)
            d_values.push_back(dmrs_values(dmrs.scrambling_id, s, l, n));
}

dmrs_matcher::match dmrs_matcher::correlate(unsigned slot_in_frame, unsigned dmrs_index) const
{
    const auto& r = d_values[std::size_t(slot_in_frame) * d_symbols + dmrs_index];
    std::complex<double> c = 0.0;
    double e = 0.0;
    std::complex<double> prev;
    for (std::size_t i = 0; i < r.size(); i++) {
        const std::complex<double> z =
            std::complex<double>(d_y[2 * i]) * std::conj(std::complex<double>(r[i]));
        if (i > 0)
            c += std::conj(prev) * z;
        e += std::norm(z);
        prev = z;
    }
    match m;
    m.rho = e > 0.0 ? std::abs(c) / e : 0.0;
    m.offset = -std::arg(c) * double(d_fft) / (4.0 * M_PI) - double(d_cp / 2);
    return m;
}

void dmrs_matcher::demodulate(const gr_complex* x, unsigned dmrs_index)
{
    if (dmrs_index >= d_symbols)
        throw_param("dmrs_index",
                    dmrs_index,
                    "must be below the DMRS symbols, " + std::to_string(d_symbols));
    d_demod.execute(x, d_y.data());
}

dmrs_matcher::match
dmrs_matcher::test(const gr_complex* x, unsigned slot_in_frame, unsigned dmrs_index)
{
    demodulate(x, dmrs_index);
    return correlate(slot_in_frame % d_slots, dmrs_index);
}

unsigned dmrs_matcher::identify(const gr_complex* x, unsigned dmrs_index, match& best)
{
    demodulate(x, dmrs_index);
    unsigned slot = 0;
    best = match();
    for (unsigned s = 0; s < d_slots; s++) {
        const match m = correlate(s, dmrs_index);
        if (m.rho > best.rho) {
            best = m;
            slot = s;
        }
    }
    return slot;
}

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
      d_miss_limit(miss_limit)
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

sync_tracker::relock sync_tracker::relock_at(std::int64_t g,
                                             std::uint64_t out_grid,
                                             unsigned dmrs_index,
                                             int slot_in_frame,
                                             unsigned slots_per_frame) const
{
    if (dmrs_index > d_repeats.size())
        throw_param("dmrs_index", dmrs_index, "must be at most the repeats, " + std::to_string(d_repeats.size()));
    if (slots_per_frame < 1 || slot_in_frame >= int(slots_per_frame))
        throw_param("slot_in_frame",
                    slot_in_frame,
                    "must be below slots_per_frame = " + std::to_string(slots_per_frame));
    const std::int64_t L = std::int64_t(d_slot);
    const std::int64_t first = g - repeat_offset(dmrs_index);
    std::int64_t s = ((std::int64_t(d_dmrs) - first) % L + L) % L; // in [0, L)
    if (s > L / 2)
        s -= L;
    std::int64_t slot = (first + s - std::int64_t(d_dmrs)) / L;
    std::uint64_t whole = 0;
    if (slot_in_frame >= 0) {
        const std::int64_t f = slots_per_frame;
        whole = std::uint64_t(((slot_in_frame - slot) % f + f) % f);
        s += std::int64_t(whole) * L;
        slot += std::int64_t(whole);
    }
    slot = std::max<std::int64_t>(slot, 0);
    return {
        s, std::max(std::uint64_t(slot), (out_grid + d_slot - 1) / d_slot), dmrs_index, whole
    };
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
            const std::int64_t at = symbol_start + d_repeats[k] - repeat_offset(j) +
                                    std::int64_t(d_cp / 2) - buf_start;
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
    return std::int64_t(slot * d_slot + d_dmrs) + std::int64_t(d_cp / 2);
}

std::uint64_t sync_tracker::first_checkable_slot(std::uint64_t g) const
{
    // smallest k with k L + dmrs + cp/2 >= g
    const std::int64_t need = std::int64_t(g) - std::int64_t(d_dmrs) - std::int64_t(d_cp / 2);
    if (need <= 0)
        return 0;
    return (std::uint64_t(need) + d_slot - 1) / d_slot;
}

bool sync_tracker::score(const dmrs_matcher::match& c, double threshold)
{
    const bool miss = !(c.rho >= threshold) || c.offset < -double(d_max_early) ||
                      c.offset > double(d_cp / 2);
    if (!miss) {
        d_misses = 0;
        return false;
    }
    d_misses++;
    return d_misses >= d_miss_limit;
}

void sync_tracker::start_check(std::uint64_t g)
{
    d_check_slot = first_checkable_slot(g);
    d_misses = 0;
}

std::uint64_t sync_tracker::until_check_end(std::uint64_t g) const
{
    const std::int64_t end = check_start(d_check_slot) + std::int64_t(check_length());
    return std::uint64_t(std::max<std::int64_t>(end - std::int64_t(g), 0));
}

sync_tracker::slot_check sync_tracker::check(const gr_complex* x,
                                             std::uint64_t g,
                                             std::size_t n,
                                             dmrs_matcher& matcher,
                                             unsigned slots_per_frame)
{
    if (n > until_check_end(g))
        throw_param("n", n, "must be at most the samples to the check window's end, " +
                                std::to_string(until_check_end(g)));
    const std::int64_t cs = check_start(d_check_slot);
    const std::int64_t ce = cs + std::int64_t(check_length());
    const std::int64_t a = std::int64_t(g);
    const std::int64_t c0 = std::max(a, cs), c1 = std::min(a + std::int64_t(n), ce);
    d_window.resize(check_length());
    if (c0 < c1)
        std::copy(x + (c0 - a), x + (c1 - a), d_window.begin() + (c0 - cs));
    slot_check r;
    if (a + std::int64_t(n) != ce)
        return r;
    r.tested = true;
    r.slot = d_check_slot++;
    r.match = matcher.test(d_window.data(), unsigned(r.slot % slots_per_frame), 0);
    r.lost = score(r.match, matcher.threshold());
    return r;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
