/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_RX_TIME_ALIGNER_H
#define INCLUDED_NRSAR_KERNEL_RX_TIME_ALIGNER_H

#include <gnuradio/nrsar/api.h>
#include <cstdint>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Symbol alignment of a received stream from rx_time stamps (ofdm_demod).
 *
 * The transmitter starts symbol 0 at a known device time T0 (timed start); a receiver
 * (USRP source) stamps a sample with its device time T (`rx_time`: whole seconds as an
 * integer, fractional seconds as a double) on its first sample and on the first sample
 * after every overflow. Sample s_tag stamped T is TX-start sample
 * s0 = s_tag + round((T0 - T) fs); the seconds are subtracted as integers and only the
 * fractions in double, so the arithmetic keeps sub-sample precision at any epoch (a plain
 * double of 1.7e9 s has a 2.4e-7 s ulp = 7 samples at 30.72 Msps).
 *
 * align() returns what a demodulator must do from the stamped sample on: drop `skip`
 * samples, then output symbol `next_symbol`, next_symbol + 1, ... (one per symbol_length
 * samples). Symbols that will never be output because the receiver started late or lost
 * samples (overflow) are counted in `lost_symbols` (relative to the symbol the caller
 * expected next).
 */
class NRSAR_API rx_time_aligner
{
public:
    struct result {
        std::uint64_t skip;        //!< samples to drop from the stamped sample on
        std::uint64_t next_symbol; //!< index of the first symbol after the skip
        std::int64_t lost_symbols; //!< next_symbol - expected (negative: time went back)
        std::int64_t tx_start_offset; //!< s0 - s_tag in samples (may be negative)
    };

    /*!
     * \param sample_rate_hz samples per second (> 0)
     * \param symbol_length samples per OFDM symbol (>= 1)
     * \param tx_start_full_s whole seconds of the TX start time T0
     * \param tx_start_frac_s fractional seconds of T0 (any finite value; folded into [0, 1))
     */
    rx_time_aligner(double sample_rate_hz,
                    std::uint64_t symbol_length,
                    std::uint64_t tx_start_full_s,
                    double tx_start_frac_s);

    //! Splits a time in seconds (>= 0) into whole and fractional seconds.
    static void split_seconds(double t, std::uint64_t& full, double& frac);

    /*!
     * \brief A stamp (full, frac) on a sample; expected_symbol = the symbol the caller would
     *        have output next without the stamp (0 before the first stamp).
     */
    result align(std::uint64_t rx_full_s, double rx_frac_s, std::uint64_t expected_symbol) const;

    /*!
     * \brief The same from a known offset: the TX start is tx_start_offset samples after
     *        the sample in question (negative: before it).
     */
    static result align_offset(std::int64_t tx_start_offset,
                               std::uint64_t symbol_length,
                               std::uint64_t expected_symbol);

    //! Samples from the stamped time to the TX start, round((T0 - T) fs).
    std::int64_t samples_until_start(std::uint64_t rx_full_s, double rx_frac_s) const;

    double sample_rate_hz() const { return d_fs; }
    std::uint64_t symbol_length() const { return d_len; }
    std::uint64_t tx_start_full_s() const { return d_full; }
    double tx_start_frac_s() const { return d_frac; }

private:
    double d_fs;
    std::uint64_t d_len;
    std::uint64_t d_full;
    double d_frac;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_RX_TIME_ALIGNER_H */
