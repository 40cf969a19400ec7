/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_TF_FILTER_H
#define INCLUDED_NRSAR_KERNEL_TF_FILTER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/params.h>
#include <volk/volk_alloc.hh>
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief One per-RE filter of eq. (25): out = y * g(s) (the strategy interface).
 *
 * Implementations: reciprocal (RF, g = 1/s), matched (MF, g = conj(s)) and Wiener
 * (WF, g = conj(s) / (|s|^2 + 1/SNR_in)). An RE the reference leaves empty (s = 0)
 * gives out = 0 for all three (RF never divides by zero). The caller passes |s|^2,
 * which it computes once per vector for the empty-RE count and the SNR estimator.
 */
class NRSAR_API re_filter
{
public:
    virtual ~re_filter() = default;
    virtual filter_type type() const = 0;
    /*!
     * out[i] = y[i] * g(s[i]), i < n. s_mag2[i] = |s[i]|^2. out may alias y but not s.
     */
    virtual void apply(const gr_complex* y,
                       const gr_complex* s,
                       const float* s_mag2,
                       gr_complex* out,
                       std::size_t n) = 0;
    //! Linear SNR_in used by WF (ignored by RF and MF).
    virtual void set_snr_linear(double snr) {}
    /*!
     * The real scale c with g(s) = c conj(s) for a constant-modulus reference of
     * |s|^2 = mag2 > 0 (RF 1/mag2, MF 1, WF 1/(mag2 + 1/SNR_in)), see
     * tf_filter::set_constant_modulus_path.
     */
    virtual float constant_modulus_scale(float mag2) const = 0;
};

//! RF, eq. (17): g = 1/s = conj(s)/|s|^2, with g = 0 where |s|^2 = 0.
class NRSAR_API rf_filter : public re_filter
{
public:
    filter_type type() const override { return filter_type::RF; }
    void apply(const gr_complex* y,
               const gr_complex* s,
               const float* s_mag2,
               gr_complex* out,
               std::size_t n) override;
    float constant_modulus_scale(float mag2) const override { return 1.0f / mag2; }

private:
    volk::vector<float> d_weight;
};

//! MF, eq. (20): g = conj(s).
class NRSAR_API mf_filter : public re_filter
{
public:
    filter_type type() const override { return filter_type::MF; }
    void apply(const gr_complex* y,
               const gr_complex* s,
               const float* s_mag2,
               gr_complex* out,
               std::size_t n) override;
    float constant_modulus_scale(float) const override { return 1.0f; }
};

//! WF, eq. (23): g = conj(s) / (|s|^2 + 1/SNR_in).
class NRSAR_API wf_filter : public re_filter
{
public:
    explicit wf_filter(double snr_linear);
    filter_type type() const override { return filter_type::WF; }
    void apply(const gr_complex* y,
               const gr_complex* s,
               const float* s_mag2,
               gr_complex* out,
               std::size_t n) override;
    void set_snr_linear(double snr) override;
    float constant_modulus_scale(float mag2) const override
    {
        return static_cast<float>(1.0 / (double(mag2) + 1.0 / d_snr));
    }
    double snr_linear() const { return d_snr; }

private:
    double d_snr;
    volk::vector<float> d_weight;
};

//! Factory by type; snr_linear is used by WF only.
NRSAR_API std::unique_ptr<re_filter> make_re_filter(filter_type type, double snr_linear);

/*!
 * \brief Method-of-moments SNR_in estimator from the echo and the known symbols.
 *
 * Model per RE: y = H s + z with P = E|H|^2 and sigma^2 = E|z|^2, H and z independent
 * of s. Then (sums over the REs in the window, each RE with its own |s|^2):
 *   E[|y|^2]         = P E|s|^2 + sigma^2
 *   E[|y|^2 |s|^2]   = P E|s|^4 + sigma^2 E|s|^2
 * two linear equations in (P, sigma^2); SNR_in = P / sigma^2. The determinant is
 * n^2 Var(|s|^2): zero for constant-modulus constellations (PSK, QPSK), where WF is MF up
 * to scale and the previous estimate is kept. Empty REs (|s|^2 = 0) carry noise only
 * and make the system regular even for PSK data in SRS modes.
 *
 * Smoothing: sums over the last `window_res` REs, kept as 64 buckets of window_res / 64
 * REs (whole vectors) plus the vectors since the last full bucket.
 * Accuracy: the regression residual has variance about sigma^4 + 2 P sigma^2, so
 * std(P_hat) = sqrt((sigma^4 + 2 P sigma^2) / (n Var|s|^2)) (Var|s|^2 = 0.40 for 256-QAM):
 * 0.17 dB in SNR at -20 dB with n = 2^24, far less at higher SNR.
 * The estimate is clamped to [min_db, max_db] = [-60, 80] dB.
 */
class NRSAR_API snr_estimator
{
public:
    static constexpr double min_db = -60.0;
    static constexpr double max_db = 80.0;

    explicit snr_estimator(std::size_t window_res = default_window_res);
    //! 2^24 REs (about 5000 symbols of 3333 REs, 0.2 s at 24 k symbols/s): at -20 dB the
    //! estimate's standard deviation is then about 0.17 dB (see docs/blocks/tf_filter.md).
    static constexpr std::size_t default_window_res = std::size_t(1) << 24;

    /*!
     * Adds one vector (y, |s|^2 of n REs); returns true when the estimate was updated
     * (false while the system is singular or the data carry no information).
     */
    bool update(const gr_complex* y, const float* s_mag2, std::size_t n);
    //! One vector's sums {sum |y|^2, sum |s|^2, sum |s|^4, sum |y|^2 |s|^2}, in float.
    using sums = std::array<float, 4>;
    //! The sums update() takes of one vector (a strip's pre-pass keeps them, docs/scale.md).
    sums sums_of(const gr_complex* y, const float* s_mag2, std::size_t n);
    //! update() of a vector of n REs from its sums_of(): the same estimate, bit for bit.
    bool update(const sums& v, std::size_t n);
    bool valid() const { return d_valid; }
    double snr_db() const { return d_snr_db; }
    double signal_power() const { return d_p; }
    double noise_power() const { return d_sigma2; }
    void reset();
    /*!
     * The whole state as doubles: {valid, snr_db, P, sigma^2, the partial bucket's n and
     * four sums, then each full bucket's n and four sums, oldest first} (9 + 5 k values).
     * A strip's task that starts at vector t sets the history of the whole stream before t
     * (histories()) and then estimates as the whole stream does from t on, bit for bit,
     * with no vector before t read (docs/scale.md).
     */
    std::vector<double> history() const;
    //! Restores a history(); std::invalid_argument names a malformed one.
    void set_history(const std::vector<double>& h);
    /*!
     * history() before each of `items` (nondecreasing, <= all.size()) of a stream of
     * vectors of n REs whose sums_of() are `all` (vector 0 first): the vectors replayed
     * through update() in order, from `start` (a history() of the vectors before `all`;
     * empty: a fresh estimator), so each history is the streaming estimator's.
     */
    static std::vector<std::vector<double>>
    histories(const std::vector<sums>& all,
              std::size_t n,
              const std::vector<std::uint64_t>& items,
              const std::vector<double>& start = {},
              std::size_t window_res = default_window_res);

private:
    struct moments {
        double n, y2, s2, s4, y2s2;
    };
    std::size_t d_window;
    static constexpr std::size_t buckets = 64;
    static void add(moments& total, const moments& m);
    std::size_t d_bucket_res;
    moments d_partial{ 0, 0, 0, 0, 0 }; // vectors not yet pooled into a bucket
    std::deque<moments> d_hist;         // full buckets, oldest first
    std::size_t d_hist_res = 0;
    volk::vector<float> d_y2;
    bool d_valid = false;
    double d_snr_db = 0.0, d_p = 0.0, d_sigma2 = 0.0;
};

/*!
 * \brief The TF filter of SPEC section 4: guards the inputs, counts empty REs,
 * estimates SNR_in (optionally) and applies the selected re_filter, one vector at a time.
 */
class NRSAR_API tf_filter
{
public:
    tf_filter(unsigned vlen,
              filter_type type,
              double snr_db,
              bool estimate_snr,
              std::size_t window_res = snr_estimator::default_window_res);
    tf_filter(const tf_filter&) = delete;
    tf_filter& operator=(const tf_filter&) = delete;
    tf_filter(tf_filter&&) = default;
    tf_filter& operator=(tf_filter&&) = default;

    /*!
     * Filters one vector of vlen REs: y (echo), s (reference), out. Returns the number of
     * non-finite input samples (in y or s) that were replaced by 0. taps2 (optional): a
     * window, each RE's real tap twice (range_ifft::window_taps2()), multiplied into out
     * after the filter in the same pass (kernel::range_compress).
     */
    std::size_t process(const gr_complex* y,
                        const gr_complex* s,
                        gr_complex* out,
                        const float* taps2 = nullptr);

    void set_filter_type(filter_type type);
    void set_snr_db(double snr_db);
    void set_estimate_snr(bool estimate);
    /*!
     * \brief The constant-modulus shortcut (on by default).
     *
     * When every RE of a vector is either empty (s = 0 exactly) or has the same |s|^2 = m0
     * (within a relative spread of cm_tolerance, i.e. float rounding of a PSK / QPSK point),
     * RF, MF and WF are all g = c conj(s) with one real c (1/m0, 1, 1/(m0 + 1/SNR_in)):
     * eq. (25) then costs one conjugate multiply and one real scale per RE instead of the
     * per-RE weight loop and a complex-by-real vector multiply. The detection is fused into
     * the empty-RE count pass that runs anyway. The result equals the general path within
     * float rounding (the weight differs from 1/|s_i|^2 by at most cm_tolerance relative).
     * An RE with 0 < |s| < ~1e-23 has |s|^2 = 0 in float and counts as empty; the shortcut
     * gives it y conj(s) c (below 1e-22 |y| / |s0|) where the general RF gives 0.
     * MF never takes it (it is conj(s) already). Off: always the general path.
     */
    void set_constant_modulus_path(bool on) { d_cm_path = on; }
    bool constant_modulus_path() const { return d_cm_path; }
    //! Vectors that took the constant-modulus shortcut so far.
    std::uint64_t constant_modulus_vectors() const { return d_cm_vectors; }
    //! Largest relative spread (max - min) / max of the non-empty |s|^2 taken as constant.
    static constexpr float cm_tolerance = 1e-6f;

    unsigned vlen() const { return d_vlen; }
    filter_type type() const { return d_filter->type(); }
    double snr_db() const { return d_snr_db; }
    bool estimate_snr() const { return d_estimate; }
    //! Latest estimate [dB] (NaN before the first valid estimate).
    double estimated_snr_db() const;
    //! SNR_in [dB] that WF uses now: the estimate when enabled and valid, else snr_db().
    double effective_snr_db() const;
    std::uint64_t empty_re_count() const { return d_empty; }
    std::uint64_t nonfinite_count() const { return d_nonfinite; }

    /*!
     * The estimator's sums of one vector (y and s guarded as process() guards them, the
     * empty REs and non-finite samples counted) without filtering it: a strip's pre-pass
     * (docs/scale.md). Returns the non-finite input samples replaced by 0.
     */
    std::size_t snr_sums(const gr_complex* y, const gr_complex* s, snr_estimator::sums& v);
    //! snr_estimator::history() of the estimate.
    std::vector<double> snr_history() const { return d_estimator.history(); }
    //! snr_estimator::set_history(); WF then uses its estimate (if valid and estimating).
    void set_snr_history(const std::vector<double>& h);

private:
    //! False when the first REs of s already fail the constant-modulus check; m0: their
    //! common |s|^2 (0 when they are all empty).
    bool may_be_constant_modulus(const gr_complex* s, float& m0);
    //! process()'s guard: y and s replaced by their finite copies, |s|^2 into d_s_mag2,
    //! the empty REs (empty) and non-finite samples counted; returns the latter.
    std::size_t guard(const gr_complex*& y, const gr_complex*& s, std::size_t& empty);

    unsigned d_vlen;
    double d_snr_db;
    bool d_estimate;
    std::unique_ptr<re_filter> d_filter;
    snr_estimator d_estimator;
    finite_guard d_guard;
    volk::vector<float> d_s_mag2;
    std::uint64_t d_empty = 0;
    std::uint64_t d_nonfinite = 0;
    bool d_cm_path = true;
    std::uint64_t d_cm_vectors = 0;

    void push_snr();
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_TF_FILTER_H */
