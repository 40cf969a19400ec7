/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_SYNC_TRACKER_H
#define INCLUDED_NRSAR_KERNEL_SYNC_TRACKER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include <gnuradio/nrsar/params.h>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The PUSCH DMRS of one symbol (38.211 6.4.1.1: its sequence depends on the slot within
 * the frame and the symbol) tested against received samples: is it there, which slot is it,
 * and when does the symbol start.
 *
 * x holds fft_size samples from cp/2 after the symbol's expected start (CFO removed); its FFT
 * gives Y on the even subcarriers 2i, Z_i = Y_2i conj(r_i) with r the candidate DMRS values and
 *   C = sum_i conj(Z_i) Z_{i+1},   rho = |C| / sum_i |Z_i|^2  in [0, 1].
 * A channel that changes little over 2 subcarriers and a timing offset e (symbol start minus
 * the expected start) give rho ~ snr / (1 + snr) (per-RE SNR) and angle(C) = -4 pi (cp/2 + e) /
 * fft_size, so e = -angle(C) fft_size / (4 pi) - cp/2 (unambiguous for e in (-fft_size/4 - cp/2,
 * fft_size/4 - cp/2)); its noise: std sqrt((n - 1) v^2 / 2 + v) / (n - 1) x fft_size / (4 pi)
 * for v = 1 / snr (1.7 samples at 3 dB, sdr20: the first-order terms telescope). Noise,
 * data or another slot's or symbol's sequence give Z_i independent
 * with random phases: C is about complex Gaussian with variance (n - 1) s^4 for n = ceil(N/2)
 * DMRS REs, so P(rho > t) = exp(-t^2 n^2 / (n - 1)); threshold() is the t where that is
 * false_alarm (1e-9: 0.26 at sdr20's n = 306, 0.11 at paper's 1667).
 */
class NRSAR_API dmrs_matcher
{
public:
    struct match {
        double rho = 0.0;    //!< |C| / sum |Z|^2
        double offset = 0.0; //!< symbol start - expected start [samples]
    };

    dmrs_matcher(const numerology& num, const dmrs_config& dmrs, double false_alarm = 1e-9);

    //! The DMRS of symbol dmrs.symbols[dmrs_index] of slot slot_in_frame against x.
    match test(const gr_complex* x, unsigned slot_in_frame, unsigned dmrs_index);
    //! The slot within the frame whose DMRS symbol dmrs_index fits x best (largest rho).
    unsigned identify(const gr_complex* x, unsigned dmrs_index, match& best);
    double threshold() const { return d_threshold; }
    //! Samples of x: fft_size; x starts cp/2 after the symbol's expected start.
    std::size_t window() const { return d_fft; }
    unsigned window_delay() const { return d_cp / 2; }

private:
    //! x's FFT into d_y, for DMRS symbol dmrs_index (checked).
    void demodulate(const gr_complex* x, unsigned dmrs_index);
    match correlate(unsigned slot_in_frame, unsigned dmrs_index) const;

    unsigned d_fft;
    unsigned d_cp;
    std::size_t d_symbols;
    unsigned d_slots; // slots per frame: each has its own DMRS sequence
    double d_threshold;
    ofdm_demodulator d_demod;
    std::vector<gr_complex> d_y;
    std::vector<std::vector<gr_complex>> d_values; // [slot * symbols + index]
};

/*!
 * \brief Keeping ofdm_sync's slot grid through gaps (lost samples) and noticing a lost lock.
 *
 * The grid counts samples of the locked burst: grid sample 0 is the first sample of slot 0
 * (ofdm_sync's output sample 0), slot k covers [k L, (k + 1) L) with L = symbols_per_slot
 * (cp + fft_size), and the slot's first DMRS symbol is expected to start (its estimate d0_hat,
 * ofdm_sync's timing) at k L + dmrs_offset.
 *
 * Gap: samples [g, g + lost) of the grid never arrived. Every slot they touch is cut; the
 * output completes the symbol the gap cuts with zeros (`pad`, so that a downstream
 * demodulator keeps its symbol boundaries), drops the received samples of the last cut slot
 * (`drop`) and resumes at the first whole slot after the gap (`resume_slot`).
 *
 * Lock check: in every slot the first DMRS symbol is tested with dmrs_matcher over the
 * window from d0_hat + cp/2 (d0_hat: its expected start) for the slot's own DMRS sequence. A
 * slot misses when rho is below the matcher's threshold (the DMRS is gone: a burst ended, the
 * grid moved by a symbol or more, or the slot's number is wrong), or the measured start is
 * more than max_early samples early (the demodulator's FFT window, placed backoff x cp inside
 * the CP, then reaches into the next symbol: what lost samples without an rx_time tag do) or
 * more than cp / 2 late. The lock is lost after miss_limit consecutive misses.
 */
class NRSAR_API sync_tracker
{
public:
    struct gap_plan {
        std::uint64_t first_slot;      //!< first slot that lost samples
        std::uint64_t resume_slot;     //!< first slot after the gap with all its samples
        std::uint64_t pad;             //!< zeros completing the symbol the gap cuts
        std::uint64_t drop;            //!< received samples dropped before resume_slot
        std::uint64_t skipped_symbols; //!< symbols from the cut one to resume_slot's first
    };

    /*!
     * \param fft_size F (even, >= 4)
     * \param cp cyclic prefix samples
     * \param symbols_per_slot symbols of a slot (>= 1)
     * \param dmrs_offset grid position of d0_hat within a slot (>= 0, < slot length)
     * \param max_early samples the plateau may start before d0_hat and still count (<= cp)
     * \param miss_limit consecutive missed slots that lose the lock (>= 1)
     */
    sync_tracker(unsigned fft_size,
                 unsigned cp,
                 unsigned symbols_per_slot,
                 std::uint64_t dmrs_offset,
                 unsigned max_early,
                 unsigned miss_limit = 2);

    std::uint64_t slot_length() const { return d_slot; }
    std::uint64_t symbol_length() const { return d_sym; }

    //! A gap of lost (> 0) samples starting at grid sample g.
    gap_plan plan_gap(std::uint64_t g, std::uint64_t lost) const;
    //! Output stopped at grid sample g: zeros that complete the symbol there.
    std::uint64_t pad_to_symbol(std::uint64_t g) const;

    struct relock {
        std::int64_t shift;    //!< grid = input + shift from here on, in (-L/2, L/2]
        std::uint64_t slot;    //!< slot the output resumes at
        unsigned dmrs_index;   //!< which DMRS symbol of the slot the acquisition found
        std::uint64_t whole_slots; //!< slots added to the shift by the slot number
    };
    /*!
     * \brief A new search found DMRS symbol dmrs_index of a slot (0: its first; which one is
     * the caller's to tell, see found_dmrs) with d0_hat at grid position g of the old grid
     * (counted by the input samples since); output has reached grid sample out_grid. The
     * shift is the gap modulo a slot in (-L/2, L/2]; when the slot's number within the frame
     * is known (slot_in_frame >= 0, from its DMRS sequence: dmrs_matcher::identify), whole
     * slots are added to the shift until the slot's number is slot_in_frame modulo
     * slots_per_frame (a gap without an rx_time tag is then known modulo a frame). Output
     * resumes at that DMRS's slot, or at the first slot starting at or after out_grid if that
     * one has begun.
     */
    relock relock_at(std::int64_t g,
                     std::uint64_t out_grid,
                     unsigned dmrs_index,
                     int slot_in_frame = -1,
                     unsigned slots_per_frame = 1) const;
    //! M at one position: x holds fft_size samples from it.
    double metric_at(const gr_complex* x) const;
    /*!
     * \brief Which DMRS symbol of its slot a search found at symbol_start (the argument
     * relock_at wants): the first j whose later DMRS symbols, where buf (buffered samples from
     * absolute index buf_start) holds them, show M >= threshold half a cp into their CP too.
     */
    unsigned found_dmrs(const gr_complex* buf,
                        std::int64_t buf_start,
                        std::size_t buffered,
                        std::int64_t symbol_start,
                        double threshold) const;
    //! Offsets (samples, > 0) of the slot's further DMRS symbols after its first.
    void set_repeats(const std::vector<std::int64_t>& offsets) { d_repeats = offsets; }
    //! Samples from the slot's first DMRS symbol to its DMRS symbol j (0 for j = 0).
    std::int64_t repeat_offset(unsigned j) const { return j == 0 ? 0 : d_repeats.at(j - 1); }

    //! Grid sample where slot k's check window starts (d0_hat + cp/2).
    std::int64_t check_start(std::uint64_t slot) const;
    //! Samples of a check window: fft_size.
    std::size_t check_length() const { return 2 * std::size_t(d_half); }
    //! First slot whose check window starts at or after grid sample g.
    std::uint64_t first_checkable_slot(std::uint64_t g) const;

    //! Scores one slot's DMRS test; true when this makes miss_limit consecutive misses.
    bool score(const dmrs_matcher::match& c, double threshold);
    //! Forgets the misses (a new lock).
    void clear_misses() { d_misses = 0; }

    /*!
     * \brief The lock check over the output stream: start_check(g) at a lock (grid sample g,
     * the first output sample, drained from the acquirer's buffer or not) or a resumed slot
     * forgets the misses and waits for the first slot whose check window starts at or after
     * g; check() then takes the derotated output as it passes.
     */
    void start_check(std::uint64_t g);
    //! Samples from grid sample g to the end of the next slot's check window (0 when at it).
    std::uint64_t until_check_end(std::uint64_t g) const;
    struct slot_check {
        bool tested = false;       //!< a check window ended here: the slot was tested
        bool lost = false;         //!< ... and made miss_limit consecutive misses
        std::uint64_t slot = 0;    //!< the tested slot
        dmrs_matcher::match match; //!< its test
    };
    /*!
     * \brief Output x (derotated) of grid samples [g, g + n), n <= until_check_end(g): keeps
     * what falls in the slot's check window; where the window ends, tests the slot's own DMRS
     * (slot modulo slots_per_frame, its first DMRS symbol) and scores it.
     */
    slot_check check(const gr_complex* x,
                     std::uint64_t g,
                     std::size_t n,
                     dmrs_matcher& matcher,
                     unsigned slots_per_frame);
    unsigned misses() const { return d_misses; }
    unsigned miss_limit() const { return d_miss_limit; }

private:
    unsigned d_half;
    unsigned d_cp;
    unsigned d_sps;
    std::uint64_t d_sym;
    std::uint64_t d_slot;
    std::uint64_t d_dmrs;
    unsigned d_max_early;
    unsigned d_miss_limit;
    unsigned d_misses = 0;
    std::vector<std::int64_t> d_repeats;
    std::uint64_t d_check_slot = 0;
    std::vector<gr_complex> d_window; // the check window (fft_size samples): memory stays bounded
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SYNC_TRACKER_H */
