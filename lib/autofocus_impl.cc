/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "autofocus_impl.h"
#include "focuser_stream.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace gr {
namespace nrsar {

namespace {
// Lines of one image when neither tags nor lines_per_aperture bound it (as image_sink).
constexpr unsigned max_untagged_lines = 65536;
constexpr double nan_v = std::numeric_limits<double>::quiet_NaN();

// The stream signature of K range bins, K checked first (both signatures use it).
gr::io_signature::sptr vectors_of(unsigned num_range_bins)
{
    return gr::io_signature::make(
        1, 1, sizeof(gr_complex) * check_at_least("num_range_bins", num_range_bins, 1u));
}

const autofocus_config& validated(const autofocus_config& cfg)
{
    cfg.validate();
    return cfg;
}
} // namespace

autofocus::sptr autofocus::make(unsigned num_range_bins, const autofocus_config& cfg)
{
    return gnuradio::make_block_sptr<autofocus_impl>(num_range_bins, cfg);
}

autofocus_impl::autofocus_impl(unsigned num_range_bins, const autofocus_config& cfg)
    : gr::block("autofocus", vectors_of(num_range_bins), vectors_of(num_range_bins)),
      d_K(num_range_bins),
      d_kernel(validated(cfg)),
      d_port(pmt::mp("phase_error"))
{
    message_port_register_out(d_port);
    set_tag_propagation_policy(TPP_DONT); // tags leave with their image's lines
    set_relative_rate(1.0);
    d_expected = cfg.lines_per_aperture;
}

autofocus_impl::~autofocus_impl() {}

void autofocus_impl::handle_tag(const tag_t& tag)
{
    if (pmt::eq(tag.key, tags::aperture_key())) {
        if (d_fill > 0)
            process_image(); // a new image before M lines: this one as it is
        if (pmt::is_integer(tag.value) || pmt::is_uint64(tag.value))
            d_index = pmt::to_uint64(tag.value);
    } else if (pmt::eq(tag.key, tags::azimuth_axis_key())) {
        const pmt::pmt_t& v = tag.value;
        std::uint64_t m = 0;
        if (parse_azimuth_lines(v, m)) {
            if (m >= 1 && m <= (1u << 30) && m > d_fill)
                d_expected = static_cast<unsigned>(m);
            if (pmt::is_number(pmt::tuple_ref(v, 1)))
                d_axes.line_spacing_m = pmt::to_double(pmt::tuple_ref(v, 1));
        } else {
            d_logger->warn("ignoring malformed azimuth_axis tag {}", pmt::write_string(v));
        }
    } else if (pmt::eq(tag.key, tags::range_axis_key())) {
        // The slant-range axis PGA's deramp needs (autofocus_config::wavelength_m).
        double first = 0.0, step = 0.0;
        std::uint64_t k = 0;
        if (parse_range_axis(tag.value, first, step, k) && k == d_K) {
            d_axes.range_first_m = first;
            d_axes.range_step_m = step;
        }
    }
    tag_t t = tag;
    t.offset = d_fill;
    d_tags.push_back(t);
}

void autofocus_impl::ingest(const gr_complex* in, unsigned n)
{
    const std::size_t need = static_cast<std::size_t>(d_fill + n) * d_K;
    if (d_buf.size() < need)
        d_buf.resize(need);
    gr_complex* dst = &d_buf[static_cast<std::size_t>(d_fill) * d_K];
    std::memcpy(dst, in, sizeof(gr_complex) * n * d_K);
    const std::size_t bad = kernel::zero_nonfinite(dst, static_cast<std::size_t>(n) * d_K);
    if (bad)
        d_nonfinite.note(d_logger, bad, d_lines_in);
    d_fill += n;
    d_lines_in += n;
}

void autofocus_impl::process_image()
{
    if (d_fill >= 4) {
        d_last = d_kernel.focus(d_buf.data(), d_fill, d_K, d_axes);
        ++d_apertures;
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::mp("aperture"), pmt::from_uint64(d_index));
        d = pmt::dict_add(d, pmt::mp("lines"), pmt::from_uint64(d_fill));
        d = pmt::dict_add(d, pmt::mp("iterations"), pmt::from_uint64(d_last.iterations));
        d = pmt::dict_add(d, pmt::mp("phase_rms_rad"), pmt::from_double(d_last.phase_rms_rad));
        d = pmt::dict_add(d, pmt::mp("entropy_before"), pmt::from_double(d_last.entropy_before));
        d = pmt::dict_add(d, pmt::mp("entropy_after"), pmt::from_double(d_last.entropy_after));
        d = pmt::dict_add(d, pmt::mp("phase_rad"), pmt::init_f64vector(d_last.phase_rad.size(), d_last.phase_rad));
        d = pmt::dict_add(d, pmt::mp("weight"), pmt::init_f64vector(d_last.weight.size(), d_last.weight));
        message_port_pub(d_port, d);
    } else {
        d_logger->info("aperture {}: {} lines, too few to autofocus, passed through", d_index, d_fill);
    }
    d_out_pos = 0;
    d_out_len = d_fill;
    d_out_tags.swap(d_tags);
    d_tags.clear();
    d_fill = 0;
    d_expected = d_kernel.config().lines_per_aperture;
    ++d_index; // the next image's, unless an aperture tag says otherwise
    d_nonfinite.rearm();
}

int autofocus_impl::drain(gr_complex* out, int noutput, int produced)
{
    if (d_out_pos >= d_out_len || produced >= noutput)
        return produced;
    const unsigned n = std::min<unsigned>(d_out_len - d_out_pos, noutput - produced);
    const std::uint64_t base = nitems_written(0) + produced;
    for (const tag_t& t : d_out_tags)
        if (t.offset >= d_out_pos && t.offset < d_out_pos + n)
            add_item_tag(0, base + (t.offset - d_out_pos), t.key, t.value, t.srcid);
    std::memcpy(out + static_cast<std::size_t>(produced) * d_K,
                &d_buf[static_cast<std::size_t>(d_out_pos) * d_K],
                sizeof(gr_complex) * n * d_K);
    d_out_pos += n;
    return produced + static_cast<int>(n);
}

void autofocus_impl::forecast(int, gr_vector_int& ninput_items_required)
{
    ninput_items_required[0] = items_until_flush(detail());
}

int autofocus_impl::general_work(int noutput_items,
                                 gr_vector_int& ninput_items,
                                 gr_vector_const_void_star& input_items,
                                 gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const std::uint64_t nread = nitems_read(0);
    const int navail = ninput_items[0];
    const bool upstream_done = input_ended(detail(), navail);

    int produced = drain(out, noutput_items, 0);
    std::vector<tag_t> tags;
    get_tags_in_range(tags, 0, d_lines_in, nread + navail);
    sort_aperture_first(tags);
    std::size_t next_tag = 0;
    // The image buffer is also the output buffer: collect only when it has been sent.
    while (produced < noutput_items && d_out_pos >= d_out_len) {
        const std::uint64_t next = d_lines_in;
        const int i = static_cast<int>(next - nread);
        if (i < navail) {
            while (next_tag < tags.size() && tags[next_tag].offset <= next) {
                handle_tag(tags[next_tag++]);
                if (d_out_pos < d_out_len)
                    break; // an aperture tag closed the previous image: send it first
            }
            if (d_out_pos < d_out_len) {
                produced = drain(out, noutput_items, produced);
                continue;
            }
            std::uint64_t end = nread + navail;
            if (next_tag < tags.size())
                end = std::min<std::uint64_t>(end, tags[next_tag].offset);
            const unsigned cap = d_expected > 0 ? d_expected : max_untagged_lines;
            const unsigned n = static_cast<unsigned>(std::min<std::uint64_t>(end - next, cap - d_fill));
            ingest(in + static_cast<std::size_t>(i) * d_K, n);
            if (d_fill == cap)
                process_image();
        } else if (upstream_done && !d_flush_done) {
            // End of stream: the partial image as it is.
            if (d_fill > 0)
                process_image();
            else
                d_flush_done = true;
        } else {
            break;
        }
        produced = drain(out, noutput_items, produced);
    }
    int consume = static_cast<int>(d_lines_in - nread);
    if (!(upstream_done && d_flush_done && d_out_pos >= d_out_len))
        consume = std::min(consume, navail - 1);
    consume_each(std::max(consume, 0));
    return produced;
}

autofocus_config autofocus_impl::config() const { return d_kernel.config(); }

void autofocus_impl::set_method(autofocus_method method)
{
    gr::thread::scoped_lock guard(d_setlock);
    autofocus_config c = d_kernel.config();
    c.method = method;
    d_kernel = kernel::autofocus(c); // validates before the swap
}

std::vector<double> autofocus_impl::phase_error_rad() const
{
    gr::thread::scoped_lock guard(const_cast<autofocus_impl*>(this)->d_setlock);
    return d_last.phase_rad;
}
double autofocus_impl::phase_rms_rad() const
{
    gr::thread::scoped_lock guard(const_cast<autofocus_impl*>(this)->d_setlock);
    return d_apertures ? d_last.phase_rms_rad : nan_v;
}
double autofocus_impl::entropy_before() const
{
    gr::thread::scoped_lock guard(const_cast<autofocus_impl*>(this)->d_setlock);
    return d_apertures ? d_last.entropy_before : nan_v;
}
double autofocus_impl::entropy_after() const
{
    gr::thread::scoped_lock guard(const_cast<autofocus_impl*>(this)->d_setlock);
    return d_apertures ? d_last.entropy_after : nan_v;
}
std::uint64_t autofocus_impl::apertures() const { return d_apertures; }
std::uint64_t autofocus_impl::nonfinite_count() const { return d_nonfinite.count(); }

} // namespace nrsar
} // namespace gr
