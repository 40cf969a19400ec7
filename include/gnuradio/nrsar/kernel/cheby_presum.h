/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_CHEBY_PRESUM_H
#define INCLUDED_NRSAR_KERNEL_CHEBY_PRESUM_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/motion_compensation.h>
#include <gnuradio/nrsar/kernel/lms_presum.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/trajectory.h>
#include <volk/volk_alloc.hh>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

//! Azimuth presumming methods ([P-2.2], SPEC section 6).
enum class presum_method {
    CHEBY,      //!< phase compensation (eqs. P-25..27) + equiripple low-pass + coherent sum (P-29)
    DROP,       //!< keep 1 of D pulses (the first paper's shortcut)
    BOXCAR,     //!< plain sum of D consecutive pulses, no compensation
    FILTER_DROP, //!< complex band-pass at the scene's Doppler centroid, keep 1 of D
    LMS          //!< adaptive line enhancer per element (normalised LMS), keep 1 of D (lms_presum.h)
};

//! What one element of the input vector is.
enum class presum_domain {
    RANGE, //!< range bin k at slant range first + k * spacing (after range_ifft)
    TF     //!< subcarrier n at fc + n Delta f (after tf_filter, before range_ifft)
};

namespace kernel {

/*!
 * \brief Options of the azimuth presummer (plain values).
 */
struct NRSAR_API presum_config {
    presum_method method = presum_method::CHEBY;
    presum_domain domain = presum_domain::RANGE;
    unsigned decim = 10;           //!< D >= 1
    unsigned num_taps = 0;         //!< FIR length L for CHEBY / FILTER_DROP / LMS; 0: 4 D
    double passband_hz = -1.0;     //!< passband half-width [Hz]; < 0: from the scene
    double stopband_hz = -1.0;     //!< stopband edge [Hz]; < 0: PRF_in / (2 D)
    double stopband_weight = 10.0; //!< Parks-McClellan weight of the stopband (passband 1)
    unsigned symbols_per_pulse = 1; //!< input pulse interval in OFDM symbols
    bool enforce_qpe_bound = true;  //!< refuse D above the eq. (P-36) bound
    double lms_step = 0.2;          //!< LMS: normalised step mu in (0, 2), misadjustment mu / (2 - mu)
    //! A strip's task (docs/scale.md): the flight's index of the first output pulse to emit;
    //! the input stream then starts at the flight's pulse first_pulse() (0: the whole flight).
    //! Not for LMS (it adapts from the first pulse).
    std::uint64_t first_output = 0;
};

/*!
 * \brief Azimuth presummer: D input pulses (K complex each) -> one output pulse.
 *
 * Streaming: push() one pulse at a time; when it completes an output group it writes
 * the output pulse. Output g is centred on input pulse g D + centre_offset() (0 or 0.5
 * pulse); it needs the input pulses up to g D + lookahead(); pulses before the stream
 * start count as zero. With first_output g0 the stream starts at the flight's pulse
 * first_pulse() = max(0, g0 D - history()) and the first output is g0: the slow time,
 * the ring's slots and the phase segments are the flight's (segments every
 * phase_segment() pulses from pulse 0, the first row reached by the same recurrence), so
 * its outputs equal the whole stream's bit for bit.
 *
 * CHEBY: every input pulse is demodulated by the phase history of a reference scatterer
 * per element (range domain: closest-approach slant range of the bin at the scene's
 * along-track centre; TF domain: the scene centre at the subcarrier's frequency), the
 * L-tap equiripple low-pass (DC gain D) is applied and the result re-modulated with the
 * reference phase at the output time: out = sum_j h_j s_j C(j), C = exp(+j 4 pi f dR / c)
 * (eqs. P-25..P-29).
 *
 * With a navigation path (not empty, not geo's ideal line) the reference scatterer's range
 * is measured from the path (los_reference: the actual line-of-sight change per pulse and
 * per element, double precision) instead of the ideal line's hyperbola, so the window is
 * summed coherently whatever the platform's sway; the output keeps the reference phase of
 * the path at the window centre. The path must cover the stream's slow times.
 */
class NRSAR_API cheby_presum
{
public:
    //! Pulses between exact evaluations of the demodulation phases (1..64, chosen so
    //! that the linear phase interpolation errs by at most 1e-4 rad; with a navigation
    //! path: of the last segment, halved from 64 until its midpoint errs at most that,
    //! within blocks of 64 pulses from the flight's pulse 0).
    unsigned phase_segment() const { return d_seg; }

    cheby_presum(const numerology& num,
                 const geometry& geo,
                 const scene& scn,
                 unsigned num_bins,
                 double first_range_m,
                 double range_bin_m,
                 const presum_config& cfg,
                 const trajectory& nav = trajectory());
    cheby_presum(const cheby_presum&) = delete;
    cheby_presum& operator=(const cheby_presum&) = delete;
    cheby_presum(cheby_presum&&) = default;
    cheby_presum& operator=(cheby_presum&&) = default;

    //! Largest D of eq. (P-36): PRF / (2 v) sqrt(lambda R0 / 2), R0 the nearest target.
    static unsigned max_decim(const numerology& num,
                              const geometry& geo,
                              const scene& scn,
                              unsigned symbols_per_pulse = 1);

    /*!
     * Feeds one input pulse (num_bins() samples). Returns true when it completed an
     * output pulse, which is then written to out (num_bins() samples).
     */
    bool push(const gr_complex* in, gr_complex* out);
    //! True when the next push() will write an output pulse.
    bool next_push_completes() const;
    //! Input pulses still needed to complete n more output pulses.
    std::uint64_t pulses_needed(std::uint64_t n) const;

    void set_range_axis(double first_range_m, double range_bin_m);
    void set_pulse_interval(double seconds);

    unsigned num_bins() const { return d_k; }
    double first_range_m() const { return d_first_m; }
    double range_bin_m() const { return d_bin_m; }
    unsigned decim() const { return d_cfg.decim; }
    presum_method method() const { return d_cfg.method; }
    presum_domain domain() const { return d_cfg.domain; }
    unsigned num_taps() const { return d_l; }
    unsigned lookahead() const { return d_b; }
    //! Pulses before g D the output g needs.
    unsigned history() const { return d_a; }
    //! The flight's pulse the input stream starts at (cfg.first_output, class doc).
    std::uint64_t first_pulse() const { return d_first_pulse; }
    double centre_offset() const { return d_centre; }
    //! Taps applied to the window's pulses, first = oldest (DC gain D; 1 for DROP).
    const std::vector<gr_complex>& taps() const { return d_taps; }
    //! Real low-pass prototype (CHEBY, FILTER_DROP; DC gain D).
    const std::vector<double>& prototype() const { return d_proto; }
    double passband_hz() const { return d_fp; }
    //! True when the prototype is the Parks-McClellan design (false: Kaiser fallback).
    bool equiripple() const { return d_equiripple; }
    double stopband_hz() const { return d_fs; }
    //! Measured on a dense grid: peak-to-peak passband ripple [dB], stopband attenuation
    //! re the DC gain [dB] (prototype).
    double passband_ripple_db() const { return d_ripple_db; }
    double stopband_atten_db() const { return d_atten_db; }
    double doppler_centroid_hz() const { return d_fdc; }
    //! Frequency of the carrier phase of element 0 (range domain: band centre).
    double phase_frequency_hz(unsigned element) const;
    double pulse_interval_s() const { return d_t_in; }
    double output_pulse_interval_s() const { return d_t_in * d_cfg.decim; }
    const std::vector<std::string>& warnings() const { return d_warnings; }
    //! The flight's index of the next input pulse (first_pulse() + pulses pushed).
    std::uint64_t pulses_in() const { return d_pushed; }
    //! The flight's index of the next output pulse (first_output + outputs written).
    std::uint64_t pulses_out() const { return d_out; }

    /*!
     * Compensation phase of eq. (P-27) [rad] for element \p element: the reference pulse
     * at slow time t_ref_s, the compensated pulse offset_pulses pulse intervals later:
     * 4 pi f (R(t_ref + offset T) - R(t_ref)) / c (double precision).
     */
    double compensation_phase(unsigned element, double t_ref_s, double offset_pulses) const;
    //! Whether the compensation follows a navigation path (false: the ideal line).
    bool follows_path() const { return !d_los.ideal(); }

private:
    double ref_range(unsigned element, double t) const; // eq. (P-25)
    void phase_row(double t, bool conj, gr_complex* row) const;
    double slow_time(std::uint64_t pulse) const;
    void start_segment(std::uint64_t pulse);
    unsigned path_segment(std::uint64_t pulse);
    void start_path_segment(std::uint64_t pulse);
    void path_ranges(double t, double* r) const; // reference ranges of every element
    void design();

    numerology d_num;
    geometry d_geo;
    presum_config d_cfg;
    unsigned d_k;
    double d_first_m, d_bin_m;
    double d_t_in;
    unsigned d_l = 1, d_a = 0, d_b = 0; // window: pulses gD - a .. gD + b
    double d_centre = 0.0;
    double d_fp = 0.0, d_fs = 0.0, d_fdc = 0.0;
    double d_ripple_db = 0.0, d_atten_db = 0.0;
    bool d_equiripple = false;
    double d_yc = 0.0, d_rc0 = 0.0; // scene centre along track, its closest slant range
    std::vector<double> d_proto;
    std::vector<gr_complex> d_taps;
    std::vector<std::string> d_warnings;
    volk::vector<gr_complex> d_ring; // L pulses x K
    std::vector<double> d_ring_t;    // slow time of each slot
    volk::vector<gr_complex> d_row;  // scratch phase row
    // Demodulation rows by recurrence in slow time: exact (double) every
    // phase_segment pulses, z <- z w in between (w from the exact phase difference).
    volk::vector<gr_complex> d_z, d_w;
    unsigned d_seg_left = 0;
    unsigned d_seg = 1;
    std::uint64_t d_seg_origin = 0; // the pulse the segments are counted from
    std::uint64_t d_seg_next = 0;   // where the next path segment starts
    void update_segment();
    std::vector<double> d_r0sq;      // per element squared closest slant range (RANGE)
    los_reference d_los;             // the navigation path's line of sight
    std::vector<double> d_ra, d_rb, d_rm; // path ranges at a segment's start, end, middle
    mutable std::vector<double> d_rrow;   // path ranges of a phase row
    std::uint64_t d_first_pulse = 0;
    std::uint64_t d_pushed = 0, d_out = 0; // the flight's pulse indices (in, out)
    double d_t0 = 0.0;        // slow time of pulse d_p0: t(p) = d_t0 + (p - d_p0) T
    std::uint64_t d_p0 = 0;
    std::unique_ptr<lms_presum> d_lms; // LMS: the adaptive line enhancer
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_CHEBY_PRESUM_H */
