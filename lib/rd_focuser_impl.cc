/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "rd_focuser_impl.h"
#include "focuser_stream.h"
#include "param_check.h"
#include <gnuradio/block_detail.h>
#include <gnuradio/buffer_reader.h>
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace gr {
namespace nrsar {

rd_focuser::sptr rd_focuser::make(const numerology& num,
                                  const geometry& geo,
                                  const scene& scn,
                                  unsigned num_range_bins,
                                  double first_range_m,
                                  double range_bin_m,
                                  const focuser_config& cfg,
                                  const trajectory& nav)
{
    check_at_least("num_range_bins", num_range_bins, 1u); // before the io_signatures
    return gnuradio::make_block_sptr<rd_focuser_impl>(
        num, geo, scn, num_range_bins, first_range_m, range_bin_m, cfg, nav);
}

namespace {
// guard: K - 2 guard_bins output bins, at least one.
unsigned output_vlen(unsigned k, const focuser_config& cfg)
{
    if (2ull * cfg.guard_bins >= k)
        throw_param("guard_bins", cfg.guard_bins, "must be below num_range_bins / 2 (" +
                                                     std::to_string(k) + " / 2)");
    return k - 2 * cfg.guard_bins;
}

} // namespace

rd_focuser_impl::rd_focuser_impl(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 unsigned num_range_bins,
                                 double first_range_m,
                                 double range_bin_m,
                                 const focuser_config& cfg,
                                 const trajectory& nav)
    : gr::block("rd_focuser",
                gr::io_signature::make(1, 1, sizeof(gr_complex) * num_range_bins),
                // out: the image; optional rd_map: the range-Doppler map after RCMC.
                gr::io_signature::make(
                    1, 2, sizeof(gr_complex) * output_vlen(num_range_bins, cfg))),
      d_K(num_range_bins),
      d_ctor_first_range(first_range_m),
      d_ctor_range_bin(default_range_bin(num, range_bin_m)),
      d_focuser(num,
                geo,
                scn,
                num_range_bins,
                cfg,
                num.symbol_s() * cfg.symbols_per_pulse,
                first_range_m,
                d_ctor_range_bin,
                nav),
      d_apertures(cfg.first_aperture),
      d_rd_apertures(cfg.first_aperture)
{
    log_warnings();
    // The output is a different domain (azimuth lines); the block places its own tags.
    set_tag_propagation_policy(TPP_DONT);
    set_relative_rate(1.0);
    // Whole apertures come out at once: an output buffer of about 2 MiB instead of GNU Radio's
    // default (16 items of 2 KiB at K = 256) cuts the scheduler round trips downstream.
    set_min_output_buffer(std::max<long>(64, (2l << 20) / (sizeof(gr_complex) * d_K)));
}

rd_focuser_impl::~rd_focuser_impl() {}

void rd_focuser_impl::log_warnings()
{
    for (const auto& w : d_focuser.take_warnings())
        d_logger->warn("{}", w);
}

void rd_focuser_impl::handle_tag(const tag_t& tag)
{
    double T = d_focuser.next_pulse_interval_s();
    double r0 = d_focuser.next_first_range_m();
    double rho = d_focuser.next_range_bin_m();
    if (!axes_from_tag(tag, d_K, d_ctor_first_range, d_ctor_range_bin, d_logger, T, r0, rho))
        return;
    switch (d_focuser.set_axes(T, r0, rho)) {
    case kernel::aperture_focuser::axes_change::APPLIED:
        log_warnings();
        break;
    case kernel::aperture_focuser::axes_change::PENDING:
        d_logger->info("axis change at input line {} applies from aperture {}",
                       tag.offset,
                       d_apertures + 1);
        break;
    case kernel::aperture_focuser::axes_change::NONE:
        break;
    }
}

void rd_focuser_impl::prepare()
{
    d_focuser.prepare();
    log_warnings(); // memory
}

void rd_focuser_impl::ingest(const gr_complex* lines, unsigned n)
{
    const auto res = d_focuser.ingest(lines, n);
    if (res.nonfinite) {
        d_nonfinite.note(d_logger, res.nonfinite, res.first_bad_line);
        d_nonfinite_pending += res.nonfinite;
    }
}

void rd_focuser_impl::focus()
{
    d_focuser.focus(d_want_rd);
    log_warnings(); // of the pending axes it applied
    d_out_pos = 0;
    d_out_len = d_focuser.image_lines();
    d_rd_pos = 0;
    d_rd_len = d_focuser.rd_lines();
}

void rd_focuser_impl::add_aperture_tags(int port,
                                        uint64_t item,
                                        uint64_t index,
                                        const pmt::pmt_t& axis_key,
                                        double first,
                                        double step,
                                        uint64_t lines)
{
    add_item_tag(port, item, tags::aperture_key(), pmt::from_uint64(index));
    add_item_tag(port,
                 item,
                 axis_key,
                 pmt::make_tuple(
                     pmt::from_double(first), pmt::from_double(step), pmt::from_uint64(lines)));
    add_item_tag(port,
                 item,
                 tags::range_axis_key(),
                 pmt::make_tuple(pmt::from_double(d_focuser.first_range_m() +
                                                  d_focuser.config().guard_bins *
                                                      d_focuser.range_bin_m()),
                                 pmt::from_double(d_focuser.range_bin_m()),
                                 pmt::from_uint64(num_output_bins())));
}

unsigned rd_focuser_impl::num_output_bins() const { return d_focuser.num_output_bins(); }

int rd_focuser_impl::drain(gr_complex* out, int noutput, int produced)
{
    while (d_out_pos < d_out_len && produced < noutput) {
        const uint64_t item = nitems_written(0) + produced;
        if (d_out_pos == 0) {
            add_aperture_tags(0,
                              item,
                              d_apertures,
                              tags::azimuth_axis_key(),
                              d_focuser.image_first_y_m(),
                              d_focuser.image_line_spacing_m(),
                              d_out_len);
            if (d_nonfinite_pending) {
                add_item_tag(0,
                             item,
                             tags::nonfinite_key(),
                             pmt::from_uint64(d_nonfinite_pending),
                             alias_pmt());
                d_nonfinite_pending = 0;
            }
            ++d_apertures;
            d_nonfinite.rearm();
        }
        const unsigned n = std::min<unsigned>(d_out_len - d_out_pos, noutput - produced);
        d_focuser.read_image(out + static_cast<size_t>(produced) * num_output_bins(), d_out_pos, n);
        d_out_pos += n;
        produced += n;
    }
    return produced;
}

int rd_focuser_impl::drain_rd(gr_complex* out, int noutput, int produced)
{
    while (d_rd_pos < d_rd_len && produced < noutput) {
        if (d_rd_pos == 0) {
            const uint64_t item = nitems_written(1) + produced;
            add_aperture_tags(1,
                              item,
                              d_rd_apertures,
                              tags::doppler_axis_key(),
                              d_focuser.rd_first_hz(),
                              d_focuser.rd_spacing_hz(),
                              d_rd_len);
            ++d_rd_apertures;
        }
        const unsigned n = std::min<unsigned>(d_rd_len - d_rd_pos, noutput - produced);
        d_focuser.read_rd_map(out + static_cast<size_t>(produced) * num_output_bins(), d_rd_pos, n);
        d_rd_pos += n;
        produced += n;
    }
    return produced;
}

void rd_focuser_impl::forecast(int, gr_vector_int& ninput_items_required)
{
    ninput_items_required[0] = items_until_flush(detail());
}

int rd_focuser_impl::general_work(int noutput_items,
                                  gr_vector_int& ninput_items,
                                  gr_vector_const_void_star& input_items,
                                  gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const uint64_t nread = nitems_read(0);
    const int navail = ninput_items[0];
    const bool upstream_done = input_ended(detail(), navail);
    prepare();
    // The map is computed only while its port is connected (otherwise no extra work).
    d_want_rd = output_items.size() > 1;
    auto* rd_out = d_want_rd ? static_cast<gr_complex*>(output_items[1]) : nullptr;

    // The tags of everything not yet ingested, in offset order.
    auto& tags = d_tags;
    get_tags_in_range(tags, 0, d_focuser.lines_in(), nread + navail);
    std::sort(tags.begin(), tags.end(), tag_t::offset_compare);
    // The block's side of the shared input loop (focuser_stream.h).
    struct side {
        rd_focuser_impl& b;
        gr_complex* out;
        gr_complex* rd_out;
        int noutput;
        int produced = 0;
        int produced_rd = 0;
        uint64_t lines_in() const { return b.d_focuser.lines_in(); }
        void handle_tag(const tag_t& t) { b.handle_tag(t); }
        unsigned room()
        {
            b.prepare(); // after an axis tag: the kernel of the new axes
            return b.d_focuser.room();
        }
        void ingest(const gr_complex* lines, unsigned n) { b.ingest(lines, n); }
        bool block_full() const { return b.d_focuser.block_full(); }
        // End of stream: emit, zero padded, every aperture whose own pulses [iM, iM + M)
        // were (partly) received.
        bool flush_due() const { return b.d_focuser.flush_due(); }
        void focus() { b.focus(); }
        bool queues_empty() const { return b.queues_empty(); }
        bool wants_input() const
        {
            return produced < noutput && b.queues_empty() && !b.d_focuser.done();
        }
        void drain()
        {
            produced = b.drain(out, noutput, produced);
            if (b.d_want_rd)
                produced_rd = b.drain_rd(rd_out, noutput, produced_rd);
        }
    } s{ *this, out, rd_out, noutput_items };
    consume_each(
        focuser_stream_loop(s, tags, in, d_K, nread, navail, upstream_done, d_flush_done));
    const int produced = s.produced, produced_rd = s.produced_rd;
    // cfg.apertures emitted and delivered: done (a strip's task stops its graph here)
    if (produced == 0 && produced_rd == 0 && d_focuser.done() && queues_empty())
        return WORK_DONE;
    if (!d_want_rd)
        return produced;
    produce(0, produced);
    produce(1, produced_rd);
    return WORK_CALLED_PRODUCE;
}

bool rd_focuser_impl::stop()
{
    gr::thread::scoped_lock guard(d_setlock);
    const uint64_t lines_in = d_focuser.lines_in();
    const uint64_t emitted = d_focuser.lines_emitted();
    if ((lines_in > emitted && !d_focuser.done()) || d_out_pos < d_out_len)
        d_logger->warn("stopped with {} input lines not yet emitted as focused lines and {} "
                       "focused lines not delivered (the flowgraph stopped before the input "
                       "ended)",
                       lines_in > emitted ? lines_in - emitted : 0,
                       d_out_len - d_out_pos);
    // The program's after-run work (images, files) gets the aperture memory back.
    d_focuser.release();
    d_out_pos = d_out_len = d_rd_pos = d_rd_len = 0;
    return true;
}

unsigned rd_focuser_impl::lines_per_aperture() const { return d_focuser.lines_per_aperture(); }
unsigned rd_focuser_impl::overlap_before() const { return d_focuser.overlap_before(); }
unsigned rd_focuser_impl::overlap_after() const { return d_focuser.overlap_after(); }
long long rd_focuser_impl::line_shift() const { return d_focuser.line_shift(); }
unsigned rd_focuser_impl::fft_size() const { return d_focuser.fft_size(); }
double rd_focuser_impl::pulse_interval_s() const { return d_focuser.pulse_interval_s(); }
double rd_focuser_impl::first_range_m() const { return d_focuser.first_range_m(); }
double rd_focuser_impl::range_bin_m() const { return d_focuser.range_bin_m(); }
double rd_focuser_impl::band_lo_hz() const { return d_focuser.band_lo_hz(); }
double rd_focuser_impl::band_hi_hz() const { return d_focuser.band_hi_hz(); }
unsigned rd_focuser_impl::band_bins() const { return d_focuser.band_bins(); }
double rd_focuser_impl::max_migration_bins() const { return d_focuser.max_migration_bins(); }
bool rd_focuser_impl::rcmc_applied() const { return d_focuser.rcmc_applied(); }
std::uint64_t rd_focuser_impl::apertures() const
{
    return d_apertures - d_focuser.config().first_aperture;
}
std::uint64_t rd_focuser_impl::stream_first_line() const
{
    return d_focuser.stream_first_line();
}
std::uint64_t rd_focuser_impl::nonfinite_count() const { return d_nonfinite.count(); }

} // namespace nrsar
} // namespace gr
