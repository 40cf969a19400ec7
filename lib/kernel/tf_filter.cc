/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include "rx_front_impl.h"
#include <gnuradio/nrsar/kernel/tf_filter.h>
#include <volk/volk.h>
#include <cmath>
#include <cstring>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {

// |s|^2 below the smallest normal float counts as an empty RE: 1/|s|^2 would overflow.
constexpr float empty_mag2 = std::numeric_limits<float>::min();

void ensure(volk::vector<float>& v, std::size_t n)
{
    if (v.size() < n)
        v.resize(n);
}

double db_to_linear(double db) { return std::pow(10.0, db / 10.0); }

// out = y conj(s) w: the common tail of RF and WF, whose real weights w differ.
void weighted_conj_product(
    const gr_complex* y, const gr_complex* s, const float* w, gr_complex* out, std::size_t n)
{
    volk_32fc_x2_multiply_conjugate_32fc(out, y, s, n);
    volk_32fc_32f_multiply_32fc(out, out, w, n);
}

// True when every |s|^2 is either exactly 0 or within cm_tolerance (relative) of the first
// non-zero one, m0. Checked in blocks of 64 REs with a vectorisable OR-reduction and an exit
// after the first block that fails: 256-QAM data fail in the first block (almost free); a
// constant-modulus vector costs one pass. (A full min / max scan of every vector measured
// 1 us per 3333 REs, 20 % of the general WF path, whatever the constellation.) An RE with
// 0 < |s|^2 < FLT_MIN (empty but not exactly 0) differs from m0 and fails the check.
bool constant_modulus(const float* m, std::size_t n, float& m0)
{
    std::size_t i = 0;
    while (i < n && m[i] == 0.0f)
        i++;
    if (i == n)
        return false;
    m0 = m[i];
    if (m0 < empty_mag2)
        return false;
    const float tol = tf_filter::cm_tolerance * m0;
    constexpr std::size_t block = 64;
    for (; i < n; i += block) {
        const std::size_t end = std::min(n, i + block);
        int bad = 0;
        for (std::size_t j = i; j < end; j++)
            bad |= int(m[j] != 0.0f) & int(std::fabs(m[j] - m0) > tol);
        if (bad)
            return false;
    }
    return true;
}

} // namespace

// ---------------------------------------------------------------- strategies, eq. (25)

void rf_filter::apply(const gr_complex* y,
                      const gr_complex* s,
                      const float* s_mag2,
                      gr_complex* out,
                      std::size_t n)
{
    // eq. (17): Y / S written as Y conj(S) / |S|^2, so an empty RE gets weight 0
    // instead of a division by zero.
    ensure(d_weight, n);
    float* w = d_weight.data();
    // Written with a 0/1 mask and no std::max: GCC (with trapping math) does not vectorise a
    // conditional 1/m. Measured at 3333 REs: 6.4 us per call with the ternary, 4.2 us now.
    for (std::size_t i = 0; i < n; i++) {
        const float m = s_mag2[i];
        const float empty = m < empty_mag2 ? 1.0f : 0.0f;
        w[i] = (1.0f - empty) / (m + empty); // empty: 0 / (m + 1) = 0
    }
    weighted_conj_product(y, s, w, out, n);
}

void mf_filter::apply(const gr_complex* y,
                      const gr_complex* s,
                      const float* /*s_mag2*/,
                      gr_complex* out,
                      std::size_t n)
{
    // eq. (20): Y conj(S); an empty RE gives 0 by itself.
    volk_32fc_x2_multiply_conjugate_32fc(out, y, s, n);
}

wf_filter::wf_filter(double snr_linear) : d_snr(snr_linear) {}

void wf_filter::set_snr_linear(double snr) { d_snr = snr; }

void wf_filter::apply(const gr_complex* y,
                      const gr_complex* s,
                      const float* s_mag2,
                      gr_complex* out,
                      std::size_t n)
{
    // eq. (23): Y conj(S) / (|S|^2 + 1/SNR_in); the regulariser keeps empty REs at 0.
    ensure(d_weight, n);
    float* w = d_weight.data();
    const float inv_snr = static_cast<float>(1.0 / d_snr);
    for (std::size_t i = 0; i < n; i++)
        w[i] = 1.0f / (s_mag2[i] + inv_snr);
    weighted_conj_product(y, s, w, out, n);
}

std::unique_ptr<re_filter> make_re_filter(filter_type type, double snr_linear)
{
    switch (type) {
    case filter_type::RF:
        return std::make_unique<rf_filter>();
    case filter_type::MF:
        return std::make_unique<mf_filter>();
    case filter_type::WF:
        return std::make_unique<wf_filter>(snr_linear);
    }
    throw_param("filter_type", static_cast<int>(type), "must be RF, MF or WF");
}

// ---------------------------------------------------------------- SNR estimator

snr_estimator::snr_estimator(std::size_t window_res)
    : d_window(window_res == 0 ? 1 : window_res),
      d_bucket_res(std::max<std::size_t>(1, d_window / buckets))
{
}

void snr_estimator::add(moments& total, const moments& m)
{
    total.n += m.n;
    total.y2 += m.y2;
    total.s2 += m.s2;
    total.s4 += m.s4;
    total.y2s2 += m.y2s2;
}

void snr_estimator::reset()
{
    d_partial = { 0, 0, 0, 0, 0 };
    d_hist.clear();
    d_hist_res = 0;
    d_valid = false;
}

snr_estimator::sums snr_estimator::sums_of(const gr_complex* y, const float* s_mag2, std::size_t n)
{
    ensure(d_y2, n);
    volk_32fc_magnitude_squared_32f(d_y2.data(), y, n);
    sums v{ 0.0f, 0.0f, 0.0f, 0.0f };
    volk_32f_accumulator_s32f(&v[0], d_y2.data(), n);
    volk_32f_accumulator_s32f(&v[1], s_mag2, n);
    volk_32f_x2_dot_prod_32f(&v[2], s_mag2, s_mag2, n);
    volk_32f_x2_dot_prod_32f(&v[3], d_y2.data(), s_mag2, n);
    return v;
}

bool snr_estimator::update(const gr_complex* y, const float* s_mag2, std::size_t n)
{
    return n != 0 && update(sums_of(y, s_mag2, n), n);
}

bool snr_estimator::update(const sums& v, std::size_t n)
{
    if (n == 0)
        return false;
    add(d_partial, { double(n), v[0], v[1], v[2], v[3] });
    // Vectors are pooled into buckets of window/64 REs, so the history holds about 64
    // entries whatever the vector length (one entry per vector would take 670 MB for
    // vlen 1), at the price of a window that moves in steps of 1/64 of its length.
    if (d_partial.n >= double(d_bucket_res)) {
        d_hist.push_back(d_partial);
        d_hist_res += std::size_t(d_partial.n);
        d_partial = { 0, 0, 0, 0, 0 };
    }
    // Drop the oldest buckets while the rest still covers the window.
    while (!d_hist.empty() &&
           d_hist_res + std::size_t(d_partial.n) - std::size_t(d_hist.front().n) >= d_window) {
        d_hist_res -= std::size_t(d_hist.front().n);
        d_hist.pop_front();
    }
    // Totals summed afresh (about 64 buckets): no drift from running subtraction.
    moments t = d_partial;
    for (const auto& m : d_hist)
        add(t, m);
    // Solve  [B/n  1  ] [P      ]   [A/n]
    //        [C/n  B/n] [sigma^2] = [D/n]   (A = sum|y|^2, B = sum|s|^2, ...)
    const double det = t.s4 - t.s2 * t.s2 / t.n; // = n Var(|s|^2) >= 0
    if (!(t.y2 > 0.0) || !(t.s4 > 0.0) || !(det > 1e-6 * t.s4))
        return false; // no energy, no reference, or constant modulus: keep the last value
    const double p = (t.y2s2 - t.y2 * t.s2 / t.n) / det;
    const double sigma2 = (t.y2 - p * t.s2) / t.n;
    d_p = p;
    d_sigma2 = sigma2;
    double db;
    if (!(p > 0.0))
        db = min_db;
    else if (!(sigma2 > 0.0))
        db = max_db;
    else
        db = std::min(max_db, std::max(min_db, 10.0 * std::log10(p / sigma2)));
    d_snr_db = db;
    d_valid = true;
    return true;
}

std::vector<double> snr_estimator::history() const
{
    const moments& m0 = d_partial;
    std::vector<double> h{ double(d_valid), d_snr_db, d_p, d_sigma2, m0.n, m0.y2, m0.s2,
                           m0.s4, m0.y2s2 };
    for (const auto& m : d_hist)
        h.insert(h.end(), { m.n, m.y2, m.s2, m.s4, m.y2s2 });
    return h;
}

void snr_estimator::set_history(const std::vector<double>& h)
{
    if (h.size() < 9 || (h.size() - 9) % 5 != 0)
        throw std::invalid_argument("history: " + std::to_string(h.size()) +
                                    " values, expected 9 + 5 k (snr_estimator::history())");
    auto at = [&](std::size_t i) {
        return moments{ h[i], h[i + 1], h[i + 2], h[i + 3], h[i + 4] };
    };
    std::deque<moments> hist;
    std::size_t res = 0;
    for (std::size_t i = 9; i < h.size(); i += 5) {
        if (!(h[i] >= double(d_bucket_res)))
            throw std::invalid_argument("history: bucket " + std::to_string((i - 9) / 5) +
                                        " holds " + std::to_string(h[i]) +
                                        " REs, a full bucket at least " +
                                        std::to_string(d_bucket_res));
        hist.push_back(at(i));
        res += std::size_t(h[i]);
    }
    if (!(h[4] >= 0.0 && h[4] < double(d_bucket_res)))
        throw std::invalid_argument("history: the partial bucket holds " +
                                    std::to_string(h[4]) + " REs, fewer than " +
                                    std::to_string(d_bucket_res) + " expected");
    d_valid = h[0] != 0.0;
    d_snr_db = h[1];
    d_p = h[2];
    d_sigma2 = h[3];
    d_partial = at(4);
    d_hist = std::move(hist);
    d_hist_res = res;
}

std::vector<std::vector<double>> snr_estimator::histories(const std::vector<sums>& all,
                                                          std::size_t n,
                                                          const std::vector<std::uint64_t>& items,
                                                          const std::vector<double>& start,
                                                          std::size_t window_res)
{
    std::vector<std::vector<double>> out;
    snr_estimator est(window_res);
    if (!start.empty())
        est.set_history(start);
    std::uint64_t v = 0;
    for (const std::uint64_t item : items) {
        if (item < v || item > all.size())
            throw std::invalid_argument("items: " + std::to_string(item) +
                                        " out of order or past the " +
                                        std::to_string(all.size()) + " vectors' sums");
        for (; v < item; v++)
            est.update(all[v], n);
        out.push_back(est.history());
    }
    return out;
}

// ---------------------------------------------------------------- the TF filter

tf_filter::tf_filter(
    unsigned vlen, filter_type type, double snr_db, bool estimate_snr, std::size_t window_res)
    : d_vlen(vlen), d_snr_db(snr_db), d_estimate(estimate_snr), d_estimator(window_res)
{
    check_at_least("vlen", vlen, 1u);
    check_range("snr_db", snr_db, -100.0, 200.0);
    d_filter = make_re_filter(type, db_to_linear(snr_db));
    d_s_mag2.resize(vlen);
}

double tf_filter::estimated_snr_db() const
{
    return d_estimator.valid() ? d_estimator.snr_db()
                               : std::numeric_limits<double>::quiet_NaN();
}

double tf_filter::effective_snr_db() const
{
    return (d_estimate && d_estimator.valid()) ? d_estimator.snr_db() : d_snr_db;
}

void tf_filter::push_snr() { d_filter->set_snr_linear(db_to_linear(effective_snr_db())); }

void tf_filter::set_filter_type(filter_type type)
{
    d_filter = make_re_filter(type, db_to_linear(effective_snr_db()));
}

void tf_filter::set_snr_db(double snr_db)
{
    check_range("snr_db", snr_db, -100.0, 200.0);
    d_snr_db = snr_db;
    push_snr();
}

void tf_filter::set_estimate_snr(bool estimate)
{
    d_estimate = estimate;
    push_snr();
}

bool tf_filter::may_be_constant_modulus(const gr_complex* s, float& m0)
{
    if (!d_cm_path || d_filter->type() == filter_type::MF)
        return false;
    // A block of the check that fails in the first REs fails the whole vector (256-QAM
    // does at once); an all-empty prefix decides nothing.
    const std::size_t prefix = std::min<std::size_t>(d_vlen, 256);
    float* m = d_s_mag2.data();
    volk_32fc_magnitude_squared_32f(m, s, prefix);
    m0 = 0.0f;
    return std::all_of(m, m + prefix, [](float x) { return x == 0.0f; }) ||
           constant_modulus(m, prefix, m0);
}

std::size_t tf_filter::process(const gr_complex* y,
                               const gr_complex* s,
                               gr_complex* out,
                               const float* taps2)
{
    const std::size_t n = d_vlen;
    if (!d_estimate && rx_front::one_pass()) {
        // One pass over y and s (measured: docs/performance.md, issue 16); the guarded
        // path below only when an input is not finite.
        using rx_front::weight_rule;
        const filter_type type = d_filter->type();
        const weight_rule rule = type == filter_type::WF   ? weight_rule::wf
                                 : type == filter_type::RF ? weight_rule::rf
                                                           : weight_rule::mf;
        const float inv_snr =
            type == filter_type::WF
                ? static_cast<float>(1.0 / static_cast<const wf_filter&>(*d_filter).snr_linear())
                : 0.0f;
        // The constant-modulus shortcut (g = c conj(s)) in the same pass, which also checks
        // the rest of the vector against the first REs' |s|^2 = m0 (issue 16: the
        // reference branch's all-ones grid took the guarded path's seven passes); a vector
        // that fails it is filtered again with the per-RE weights.
        float m0 = 0.0f;
        bool cm = may_be_constant_modulus(s, m0);
        if (cm && m0 == 0.0f) { // an all-empty prefix: the whole vector decides
            volk_32fc_magnitude_squared_32f(d_s_mag2.data(), s, n);
            cm = constant_modulus(d_s_mag2.data(), n, m0);
        }
        rx_front::pass_sums r;
        if (cm)
            r = rx_front::filter_pass(weight_rule::scale,
                                      y,
                                      s,
                                      d_filter->constant_modulus_scale(m0),
                                      out,
                                      n,
                                      taps2,
                                      m0,
                                      cm_tolerance * m0);
        if (!cm || r.off_modulus) {
            cm = false;
            r = rx_front::filter_pass(rule, y, s, inv_snr, out, n, taps2);
        }
        if (std::isfinite(r.sum)) {
            d_empty += r.empty;
            d_cm_vectors += cm;
            return 0;
        }
    }
    const gr_complex *yy = y, *ss = s;
    std::size_t empty = 0;
    const std::size_t bad = guard(yy, ss, empty);
    const float* m = d_s_mag2.data();

    if (d_estimate && d_estimator.update(yy, m, n))
        push_snr();

    float m0 = 0.0f;
    // MF is conj(s) already: the check would only cost (measured +0.5 us per 3333 REs).
    if (d_cm_path && d_filter->type() != filter_type::MF && empty < n &&
        constant_modulus(m, n, m0)) {
        // Constant modulus (SPEC 4: RF, MF and WF are the same up to scale): g = c conj(s)
        // (eq. 17, 20, 23 with |s|^2 = m0).
        const float c = d_filter->constant_modulus_scale(m0);
        volk_32fc_x2_multiply_conjugate_32fc(out, yy, ss, n);
        if (c != 1.0f)
            volk_32f_s32f_multiply_32f(
                reinterpret_cast<float*>(out), reinterpret_cast<const float*>(out), c, 2 * n);
        d_cm_vectors++;
    } else {
        d_filter->apply(yy, ss, m, out, n);
    }
    if (taps2) // the same product as range_ifft's window pass
        rx_front::window_pass(out, taps2, out, n);
    return bad;
}

std::size_t tf_filter::guard(const gr_complex*& y, const gr_complex*& s, std::size_t& empty)
{
    const std::size_t n = d_vlen;
    std::size_t bad_y = 0, bad_s = 0;
    y = d_guard.guard(y, n, bad_y, 0);
    s = d_guard.guard(s, n, bad_s, 1);
    float* m = d_s_mag2.data();
    volk_32fc_magnitude_squared_32f(m, s, n);
    empty = 0;
    for (std::size_t i = 0; i < n; i++)
        empty += std::size_t(m[i] < empty_mag2);
    d_empty += empty;
    d_nonfinite += bad_y + bad_s;
    return bad_y + bad_s;
}

std::size_t tf_filter::snr_sums(const gr_complex* y, const gr_complex* s, snr_estimator::sums& v)
{
    std::size_t empty = 0;
    const std::size_t bad = guard(y, s, empty);
    v = d_estimator.sums_of(y, d_s_mag2.data(), d_vlen);
    return bad;
}

void tf_filter::set_snr_history(const std::vector<double>& h)
{
    d_estimator.set_history(h);
    push_snr();
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
