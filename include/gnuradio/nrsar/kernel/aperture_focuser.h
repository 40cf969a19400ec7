/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_APERTURE_FOCUSER_H
#define INCLUDED_NRSAR_KERNEL_APERTURE_FOCUSER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/focuser_config.h>
#include <gnuradio/nrsar/kernel/rd_focuser.h>
#include <gnuradio/nrsar/params.h>
#include <volk/volk_alloc.hh>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief Streaming range-Doppler focuser (SPEC section 7): pulses in, one aperture of M
 * focused lines out at a time, by overlap-save around kernel::rd_focuser.
 *
 * Layout: aperture i holds the image lines [i M + s, i M + s + M), s = line_shift(), the
 * azimuth shift E(f_c, R_mid) = f_c lambda R_mid / (2 v^2 T) of the scene band centre f_c
 * at the scene's mid range. Its processing block is the P = before + M + after pulses
 * starting `before` lines ahead of the window (overlap-save: image line t0 needs the
 * pulses [t0 - e_hi, t0 - e_lo] of the band's azimuth extent); without overlap each
 * aperture is focused alone, circularly, and rotated by s. Pulses before the stream start
 * are zero; pulses focusing before the first output line are skipped. Input lines are
 * stored range-major (the kernel's layout), transposed while they are hot; non-finite
 * samples are zeroed and counted. A change of the axes (T, first range, bin spacing) while
 * lines are buffered applies from the next aperture, keeping history and look-ahead.
 *
 * Use: while (room()) ingest(...); when block_full() (or at the end of the stream while
 * flush_due()) focus(), then read the aperture with read_image() (and read_rd_map()).
 * Warnings (aliasing band, memory) are collected for the caller to log: take_warnings().
 */
class NRSAR_API aperture_focuser
{
public:
    //! Validates geo, scn, cfg and the axes (std::invalid_argument naming the parameter).
    //! nav: the navigation path for cfg.moco (rd_focuser::set_motion; empty: the ideal line).
    aperture_focuser(const numerology& num,
                     const geometry& geo,
                     const scene& scn,
                     unsigned num_range_bins,
                     const focuser_config& cfg,
                     double pulse_interval_s,
                     double first_range_m,
                     double range_bin_m,
                     const trajectory& nav = trajectory());
    aperture_focuser(const aperture_focuser&) = delete;
    aperture_focuser& operator=(const aperture_focuser&) = delete;

    //! What set_axes() did.
    enum class axes_change {
        NONE,    //!< the axes are the current (or already pending) ones
        APPLIED, //!< nothing buffered yet: applied from the first line
        PENDING  //!< applies from the next aperture
    };
    //! Whether two axis values differ beyond rounding (relative 1e-9).
    static bool differs(double a, double b);
    //! New axes (e.g. from tags); see axes_change.
    axes_change set_axes(double pulse_interval_s, double first_range_m, double range_bin_m);
    //! The axes the next aperture will use: the pending ones, else the current ones.
    double next_pulse_interval_s() const { return d_pending ? d_pending_T : d_T; }
    double next_first_range_m() const { return d_pending ? d_pending_first_range : d_first_range; }
    double next_range_bin_m() const { return d_pending ? d_pending_range_bin : d_range_bin; }

    //! Builds the focusing kernel and lays the block out for the current axes if that is
    //! not done yet (FFT plans are made here); ingest() and focus() need it.
    void prepare();

    //! Lines ingest() can take before the block is full (skipped pulses count; 0 while the
    //! zero lines before the stream's start still fill it: ingest(lines, 0) enters them).
    unsigned room() const
    {
        const unsigned free = d_before + d_M + d_after - d_fill;
        return free > d_lead ? free - static_cast<unsigned>(d_lead) : 0u;
    }
    //! Result of ingest(): non-finite samples found (and zeroed) and the input line of
    //! the first one.
    struct ingest_result {
        std::uint64_t nonfinite = 0;
        std::uint64_t first_bad_line = 0;
    };
    //! Appends n <= room() line-major lines of num_range_bins() samples.
    ingest_result ingest(const gr_complex* lines, unsigned n);
    bool block_full() const { return d_fill == d_before + d_M + d_after; }
    //! At the end of the stream: an aperture whose own pulses were (partly) received is
    //! not emitted yet; focus() zero-pads it.
    bool flush_due() const { return !done() && d_aperture_start < d_line0 + d_lines_in; }
    //! cfg.apertures apertures were focused: nothing more is ingested or emitted.
    bool done() const { return d_cfg.apertures > 0 && d_focused >= d_cfg.apertures; }
    //! The flight's line of the stream's first input line (cfg.first_aperture; 0 without).
    std::uint64_t stream_first_line() const { return d_line0; }
    /*!
     * \brief Focuses the block (zero-padded if partial) into the next aperture, shifts the
     * history and applies pending axes. with_rd_map: also the range-Doppler map.
     */
    void focus(bool with_rd_map);

    //! The last aperture: its lines, first along-track position and spacing [m].
    unsigned image_lines() const { return d_image_lines; }
    double image_first_y_m() const { return d_image_y0; }
    double image_line_spacing_m() const { return d_image_dy; }
    //! Copies image lines [first, first + n) of the inner num_output_bins() bins to dst.
    void read_image(gr_complex* dst, unsigned first, unsigned n) const;
    //! The last aperture's range-Doppler map (focus(true)): lines, first Doppler, spacing.
    unsigned rd_lines() const { return d_rd_lines; }
    double rd_first_hz() const { return d_rd_f0; }
    double rd_spacing_hz() const { return d_rd_df; }
    void read_rd_map(gr_complex* dst, unsigned first, unsigned n) const;

    //! Frees the block, the last aperture and the range-Doppler map (the flowgraph has
    //! stopped and its lines are delivered): the next prepare() lays the block out anew.
    void release();

    //! Warnings since the last call (the caller logs them).
    std::vector<std::string> take_warnings();

    unsigned num_range_bins() const { return d_K; }
    //! K - 2 guard_bins.
    unsigned num_output_bins() const { return d_K - 2 * d_cfg.guard_bins; }
    const focuser_config& config() const { return d_cfg; }
    unsigned lines_per_aperture() const { return d_M; }
    unsigned overlap_before() const { return d_before; }
    unsigned overlap_after() const { return d_after; }
    long long line_shift() const { return d_line_shift; }
    unsigned fft_size() const;
    double pulse_interval_s() const { return d_T; }
    double first_range_m() const { return d_first_range; }
    double range_bin_m() const { return d_range_bin; }
    double band_lo_hz() const;
    double band_hi_hz() const;
    unsigned band_bins() const;
    double max_migration_bins() const;
    bool rcmc_applied() const;
    //! Input lines ingested (skipped pulses included).
    std::uint64_t lines_in() const { return d_lines_in; }
    //! Input lines covered by the apertures focused so far (M per aperture).
    std::uint64_t lines_emitted() const
    {
        return d_aperture_start - d_cfg.first_aperture * d_M;
    }

private:
    const numerology d_num;
    const geometry d_geo;
    const scene d_scn;
    const focuser_config d_cfg;
    const unsigned d_K;

    // Current processing parameters.
    double d_T = 0.0;
    double d_first_range = 0.0;
    double d_range_bin = 0.0;
    double d_scene_lo_hz = 0.0; // scene band with margin
    double d_scene_hi_hz = 0.0;
    unsigned d_M = 0;
    unsigned d_before = 0;
    unsigned d_after = 0;
    long long d_line_shift = 0; // output window offset from the aperture's pulses [lines]
    std::uint64_t d_skip = 0;   // pulses still to drop before the first block
    std::uint64_t d_lead = 0;   // zero lines before the stream that the first block lacks
    std::unique_ptr<rd_focuser> d_kernel; // built lazily (it owns the FFT plans)
    std::shared_ptr<const los_reference> d_los; // the navigation's line of sight (moco)
    double d_los_range = 0.0;                   // its first-order reference range

    // Pending axes (applied at the next aperture boundary).
    bool d_pending = false;
    double d_pending_T = 0.0;
    double d_pending_first_range = 0.0;
    double d_pending_range_bin = 0.0;

    // calloc'd, elements left unconstructed: the zero history of the first block (the lines
    // before the stream start) stays in pages the kernel maps only when written, so it
    // costs no memory (the paper demo: 63 % of each focuser's 94 MB block).
    template <typename T>
    struct zero_pages {
        using value_type = T;
        zero_pages() = default;
        template <typename U>
        zero_pages(const zero_pages<U>&) noexcept
        {
        }
        T* allocate(std::size_t n)
        {
            void* p = std::calloc(n, sizeof(T));
            if (!p)
                throw std::bad_alloc();
            return static_cast<T*>(p);
        }
        void deallocate(T* p, std::size_t) noexcept { std::free(p); }
        template <typename U>
        void construct(U*) noexcept
        {
        }
        template <typename U>
        bool operator==(const zero_pages<U>&) const noexcept
        {
            return true;
        }
        template <typename U>
        bool operator!=(const zero_pages<U>&) const noexcept
        {
            return false;
        }
    };
    std::vector<gr_complex, zero_pages<gr_complex>> d_block; // K x (before + M + after):
                                                             // range-major input lines
    unsigned d_fill = 0;              // lines in d_block
    unsigned d_written = 0;           // lines [0, d_written) of each row may be non-zero
    unsigned d_shift = 0;             // lines focus() left to drop from the block's front
    unsigned d_layout_before = 0;     // history lines d_block was laid out with
    unsigned d_layout_lines = 0;      // lines per range bin (row length) of d_block
    volk::vector<gr_complex> d_out;   // M x K focused lines of the last aperture
    unsigned d_image_lines = 0;
    double d_image_y0 = 0.0;
    double d_image_dy = 0.0;
    volk::vector<gr_complex> d_rd; // band bins x K, ascending Doppler
    unsigned d_rd_lines = 0;
    double d_rd_f0 = 0.0;
    double d_rd_df = 0.0;

    std::uint64_t d_lines_in = 0;       // input lines ingested
    std::uint64_t d_aperture_start = 0; // the flight's line of the next aperture
    std::uint64_t d_line0 = 0;          // the flight's line of the stream's first line
    std::uint64_t d_focused = 0;        // apertures focused
    double d_next_y = 0.0; // along-track position of the next aperture's first line
    std::vector<std::string> d_warnings;

    void configure(double T, double first_range, double range_bin);
    void apply_shift(); // drops the d_shift lines focus() left (before new lines come in)
    rd_block make_block() const; // the kernel's block for the current parameters
    //! The first line of aperture i's block relative to i M: shift - before, 0 circular.
    long long block_offset() const;
    void copy_inner(gr_complex* dst, const gr_complex* src, unsigned lines) const; // guard
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_APERTURE_FOCUSER_H */
