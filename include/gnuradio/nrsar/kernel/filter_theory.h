/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_FILTER_THEORY_H
#define INCLUDED_NRSAR_KERNEL_FILTER_THEORY_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Moments of the per-RE filter over a constellation (SPEC section 8, eqs. (25), (56)).
 *
 * With g the filter coefficient of eq. (25) for symbol s and chi = s g (real for RF, MF
 * and WF), the expectations are taken over the given points, each equally likely.
 */
struct NRSAR_API filter_moments {
    double mean_chi = 0.0; //!< E{chi}
    double var_chi = 0.0;  //!< Var(chi) = E{chi^2} - E{chi}^2
    double mean_g2 = 0.0;  //!< E{|g|^2}
};

/*!
 * \brief E{chi}, Var(chi), E{|g|^2} for filter f at linear SNR_in snr_in.
 *
 * g = 1/s (RF), conj(s) (MF), conj(s) / (|s|^2 + 1/snr_in) (WF), eq. (25).
 * Throws std::invalid_argument for an empty constellation, a non-finite or zero point,
 * or a non-finite or non-positive snr_in.
 */
NRSAR_API filter_moments compute_filter_moments(const std::vector<gr_complex>& points,
                                                filter_type f,
                                                double snr_in);

/*!
 * \brief NMSE_theory = (Var(chi) + E{|g|^2} / SNR_in) / E{chi}^2 (SPEC section 8), linear.
 */
NRSAR_API double nmse_theory(const std::vector<gr_complex>& points, filter_type f, double snr_in);

//! nmse_theory in dB, with SNR_in given in dB.
NRSAR_API double nmse_theory_db(const std::vector<gr_complex>& points,
                                filter_type f,
                                double snr_in_db);

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_FILTER_THEORY_H */
