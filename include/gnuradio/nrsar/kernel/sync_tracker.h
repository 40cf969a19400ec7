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
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

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
 * Lock check: in every slot the Schmidl & Cox metric M (sc_acquirer's) is computed over the
 * window of positions [d0_hat - cp, d0_hat + cp] and the plateau located as the acquirer
 * does (the cp + 1 positions with the largest sum of M). A slot misses when that plateau's
 * peak M is below the threshold, or it starts more than max_early samples before d0_hat (the
 * demodulator's FFT window, placed backoff x cp inside the CP, then reaches into the next
 * symbol: what lost samples without an rx_time tag do) or more than cp / 2 after it (the
 * window far into the CP, where the channel's delay spread reaches). The timing tests read
 * the mean offset of the last offset_window (3) slots whose peak passed: a gap moves every
 * later slot by the same amount, noise scatters each slot's plateau on its own (a gap of
 * more than 3 max_early is seen as soon as with one slot's offset). The lock is lost after
 * miss_limit consecutive misses.
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
    struct check {
        double mmax = 0.0;       //!< peak M in the plateau window
        std::int64_t offset = 0; //!< plateau start - d0_hat [samples]
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
    };
    /*!
     * \brief A new search found DMRS symbol dmrs_index of a slot (0: its first; which one is
     * the caller's to tell, see metric_at) with d0_hat at grid position g of the old grid
     * (counted by the input samples since); output has reached grid sample out_grid. The
     * shift is the gap modulo a slot in (-L/2, L/2] (lost samples without an rx_time tag are
     * taken to be fewer than half a slot). Output resumes at that DMRS's slot, or at the
     * first slot starting at or after out_grid if that one has begun.
     */
    relock relock_at(std::int64_t g, std::uint64_t out_grid, unsigned dmrs_index) const;
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

    //! Grid sample where slot k's check window starts (d0_hat - cp; may be < k L).
    std::int64_t check_start(std::uint64_t slot) const;
    //! Samples of a check window: 3 cp + fft_size.
    std::size_t check_length() const { return d_check_len; }
    //! First slot whose check window starts at or after grid sample g.
    std::uint64_t first_checkable_slot(std::uint64_t g) const;

    /*!
     * \brief M over the check window x (check_length() samples, window start = d0_hat - cp)
     * and its plateau: peak M of the best cp + 1 positions and their start relative to d0_hat.
     */
    check measure(const gr_complex* x) const;

    //! Scores one slot; true when this makes miss_limit consecutive misses (lock lost).
    bool score(const check& c, double threshold);
    //! Forgets the misses and the offsets (a new lock).
    void clear_misses()
    {
        d_misses = 0;
        d_offset_count = 0;
    }
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
    std::size_t d_check_len;
    unsigned d_misses = 0;
    static constexpr std::size_t offset_window = 3;
    std::array<std::int64_t, offset_window> d_offsets{};
    std::size_t d_offset_count = 0;
    std::vector<std::int64_t> d_repeats;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SYNC_TRACKER_H */
