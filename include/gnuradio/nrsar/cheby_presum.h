/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_CHEBY_PRESUM_H
#define INCLUDED_NRSAR_CHEBY_PRESUM_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Azimuth presummer [P-2.2]: one output pulse per D input pulses, at PRF / D
 * (SPEC section 6). Thin adapter of kernel::cheby_presum.
 * \ingroup nrsar
 *
 * in: vectors of num_bins complex, one pulse per item (range-compressed or TF-filtered).
 * out: vectors of num_bins complex at PRF / D. Tags: `pulse_interval` (double, T D) and
 * `range_axis` (RANGE domain) on the first output item; the tags of the first input
 * pulse of every group of D go to that group's output; a `range_axis` tag on the input
 * updates the compensation table (and is forwarded); a `pulse_interval` tag on the input
 * updates T; `nonfinite` (uint64) on an output whose window held zeroed samples.
 */
class NRSAR_API cheby_presum : virtual public gr::block
{
public:
    typedef std::shared_ptr<cheby_presum> sptr;

    /*!
     * \param num numerology (Tsym, Delta f, N)
     * \param geo geometry (fc, v, H, track start, Ta)
     * \param scn scene: Doppler band (compute_extent), scene centre, eq. (P-36) bound
     * \param num_bins K, complex samples per pulse
     * \param first_range_m slant range of bin 0 [m] (RANGE; a range_axis tag wins)
     * \param range_bin_m bin spacing [m] (RANGE; a range_axis tag wins)
     * \param cfg method (CHEBY, DROP, BOXCAR, FILTER_DROP, LMS), decimation D (refused above
     *        eq. (P-36) unless enforce_qpe_bound is false; not for DROP, LMS), domain (RANGE after
     *        range_ifft, TF before it with num_bins = N), FIR length (0 = 4 D), passband
     *        half-width (<= 0: from the scene, CHEBY: the Doppler spread left after
     *        compensation; FILTER_DROP: half the scene band; plus 10 % of the band + 2 / Ta),
     *        stopband edge (<= 0: PRF / (2 D)), Parks-McClellan stopband weight, input pulse
     *        interval in OFDM symbols, LMS normalised step: see kernel::presum_config
     * \param nav navigation path (CHEBY): the compensation follows the line of sight from
     *        it to the reference scatterers, pulse by pulse; empty (the default) or geo's
     *        ideal line: the ideal line, with its phase tables
     */
    static sptr make(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     unsigned num_bins = 256,
                     double first_range_m = 0.0,
                     double range_bin_m = 1.0,
                     const kernel::presum_config& cfg = kernel::presum_config(),
                     const trajectory& nav = trajectory());

    //! eq. (P-36) bound for these parameters.
    static unsigned max_decim(const numerology& num,
                              const geometry& geo,
                              const scene& scn,
                              unsigned symbols_per_pulse = 1);

    virtual unsigned decim() const = 0;
    virtual presum_method method() const = 0;
    virtual presum_domain domain() const = 0;
    virtual unsigned num_bins() const = 0;
    virtual unsigned num_taps() const = 0;
    //! Pulses after g D the output g needs.
    virtual unsigned lookahead() const = 0;
    //! Pulses before g D the output g needs.
    virtual unsigned history() const = 0;
    //! The flight's pulse the input starts at (cfg.first_output: a strip's task).
    virtual std::uint64_t first_pulse() const = 0;
    //! Output g is centred on input pulse g D + centre_offset().
    virtual double centre_offset() const = 0;
    //! Applied taps, oldest pulse first (complex for FILTER_DROP; empty for LMS, adaptive).
    virtual std::vector<gr_complex> taps() const = 0;
    //! Real low-pass prototype (DC gain D).
    virtual std::vector<double> prototype() const = 0;
    virtual double passband_hz() const = 0;
    //! True: Parks-McClellan prototype; false: Kaiser-windowed sinc (see warnings()).
    virtual bool equiripple() const = 0;
    virtual double stopband_hz() const = 0;
    virtual double passband_ripple_db() const = 0;
    virtual double stopband_atten_db() const = 0;
    virtual double doppler_centroid_hz() const = 0;
    virtual double phase_frequency_hz(unsigned element) const = 0;
    virtual double output_pulse_interval_s() const = 0;
    //! eq. (P-27) phase [rad] of element, reference pulse at t_ref_s, offset in pulses.
    virtual double compensation_phase(unsigned element, double t_ref_s, double offset) const = 0;
    virtual std::vector<std::string> warnings() const = 0;
    virtual std::uint64_t nonfinite_count() const = 0;
    //! Whether the compensation follows the navigation path (false: the ideal line).
    virtual bool follows_path() const = 0;
    //! Pulses between exact phase rows (the last segment's, with a path).
    virtual unsigned phase_segment() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_CHEBY_PRESUM_H */
