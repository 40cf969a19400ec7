/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TF_FILTER_H
#define INCLUDED_NRSAR_TF_FILTER_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Per-RE time-frequency filter of SPEC section 4, eq. (25)-(26).
 * \ingroup nrsar
 *
 * Y_tf = Y * G with, per resource element, RF g = 1/s, MF g = conj(s) or
 * WF g = conj(s) / (|s|^2 + 1/SNR_in). Input 0 (`echo`): received grid Y, one OFDM symbol
 * of vlen REs per item. Input 1 (`reference`): the transmitted symbols S of the same
 * REs. Output (`out`): Y_tf, vlen REs per item.
 *
 * REs the reference leaves empty (|s|^2 = 0, e.g. outside the SRS comb) give 0 for all
 * three filters and are counted (empty_re_count). Non-finite input samples are replaced
 * by 0, counted (nonfinite_count), logged once and reported by a tags::nonfinite_key()
 * tag (uint64 count) on the output item they affected. The tags of input 0 (the echo)
 * propagate; those of input 1 (the transmitted grid, usually the same tags) do not, so
 * none is doubled.
 *
 * With estimate_snr, WF uses a method-of-moments estimate of SNR_in from the echo and
 * the known symbols over a sliding window of 2^24 (16.8 M) REs (see
 * kernel::snr_estimator); until the first valid estimate, and for constant-modulus
 * constellations (where WF is MF up to scale), it uses snr_db.
 */
class NRSAR_API tf_filter : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<tf_filter> sptr;

    /*!
     * \param vlen REs per item (the numerology's num_subcarriers), >= 1
     * \param type filter: filter_type::RF, MF or WF
     * \param snr_db SNR_in [dB] per RE for WF (finite, in [-100, 200]); default 20
     * \param estimate_snr estimate SNR_in from the data instead (WF), default false
     */
    static sptr make(unsigned vlen,
                     gr::nrsar::filter_type type = gr::nrsar::filter_type::WF,
                     double snr_db = 20.0,
                     bool estimate_snr = false);

    virtual void set_filter_type(gr::nrsar::filter_type type) = 0;
    virtual void set_snr_db(double snr_db) = 0;
    virtual void set_estimate_snr(bool estimate) = 0;
    /*!
     * Constant-modulus shortcut (default on): a vector whose non-empty reference REs all
     * have the same |s|^2 (PSK, QPSK; empty REs exactly 0) is filtered as g = c conj(s)
     * with one real c (RF 1/|s|^2, MF 1, WF 1/(|s|^2 + 1/SNR_in)): exact up to float
     * rounding, about 10 % less kernel time for RF and WF (MF is conj(s) already and
     * never takes it). Off: always the per-RE weights.
     */
    virtual void set_constant_modulus_path(bool on) = 0;
    /*!
     * Threads per work() call, 1 (default) or 2: with 2, the second half of the call's
     * items is filtered on a persistent second thread (kernel::split_worker; not while
     * estimate_snr is on: the estimator needs the vectors in order). See
     * docs/performance.md for when it pays.
     */
    virtual void set_threads(unsigned threads) = 0;
    virtual unsigned threads() const = 0;

    //! The filter in use (named like the enum; qualify the enum inside the class).
    virtual gr::nrsar::filter_type filter_type() const = 0;
    virtual double snr_db() const = 0;
    virtual bool estimate_snr() const = 0;
    //! Latest SNR_in estimate [dB]; NaN before the first valid estimate.
    virtual double estimated_snr_db() const = 0;
    //! REs with an empty reference (|s|^2 = 0) seen so far.
    virtual std::uint64_t empty_re_count() const = 0;
    //! Non-finite input samples replaced by 0 so far.
    virtual std::uint64_t nonfinite_count() const = 0;
    //! Whether the constant-modulus shortcut is enabled.
    virtual bool constant_modulus_path() const = 0;
    //! Items (vectors) filtered by the constant-modulus shortcut so far.
    virtual std::uint64_t constant_modulus_items() const = 0;

    /*!
     * A strip's pre-pass (docs/scale.md, "The SNR estimate"): with on, each item is not
     * filtered (the output is zeros) but its SNR-estimator sums are kept (snr_sums()), the
     * inputs guarded and counted as filtering guards them.
     */
    virtual void set_snr_prepass(bool on) = 0;
    /*!
     * The pre-pass's sums, four floats per item in stream order: sum |y|^2, sum |s|^2,
     * sum |s|^4, sum |y|^2 |s|^2 (kernel::snr_estimator::sums_of).
     */
    virtual std::vector<float> snr_sums() const = 0;
    //! The SNR estimator's state (kernel::snr_estimator::history()).
    virtual std::vector<double> snr_history() const = 0;
    /*!
     * Starts the SNR estimator from a history (snr_histories()): a stream started at item
     * t with the whole stream's history before t estimates, and filters, as the whole
     * stream does from t on, bit for bit. Set it before the first item. ValueError for a
     * malformed one.
     */
    virtual void set_snr_history(const std::vector<double>& history) = 0;
    /*!
     * The SNR estimator's history before each of `items` (nondecreasing, at most the
     * number of items in sums, counted from the first) of vlen-RE items whose pre-pass
     * sums are `sums` (snr_sums(), in stream order): the items replayed through the
     * estimator in order, from `history` (that of the stream before them; empty: the
     * stream's start). A stream's sums can so be replayed a part at a time.
     */
    static std::vector<std::vector<double>>
    snr_histories(unsigned vlen,
                  const std::vector<float>& sums,
                  const std::vector<std::uint64_t>& items,
                  const std::vector<double>& history = {});
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TF_FILTER_H */
