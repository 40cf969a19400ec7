/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "image_sink_impl.h"
#include "focuser_stream.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gr {
namespace nrsar {

namespace {
// Lines of one image when neither tags nor lines_per_aperture bound it (512 MiB at K = 1024).
constexpr unsigned max_untagged_lines = 65536;

kernel::image_file_config make_config(const std::string& prefix,
                                      bool npy,
                                      bool png,
                                      double dr,
                                      image_colormap cmap,
                                      unsigned keep)
{
    kernel::image_file_config c;
    c.prefix = prefix;
    c.npy = npy;
    c.png = png;
    c.dynamic_range_db = dr;
    c.colormap = cmap;
    c.keep = keep;
    c.validate();
    return c;
}
} // namespace

image_sink::sptr image_sink::make(unsigned num_range_bins,
                                  const std::string& prefix,
                                  bool write_npy,
                                  bool write_png,
                                  double dynamic_range_db,
                                  image_colormap colormap,
                                  unsigned keep,
                                  unsigned lines_per_aperture)
{
    return gnuradio::make_block_sptr<image_sink_impl>(num_range_bins,
                                                      prefix,
                                                      write_npy,
                                                      write_png,
                                                      dynamic_range_db,
                                                      colormap,
                                                      keep,
                                                      lines_per_aperture);
}

image_sink_impl::image_sink_impl(unsigned num_range_bins,
                                 const std::string& prefix,
                                 bool write_npy,
                                 bool write_png,
                                 double dynamic_range_db,
                                 image_colormap colormap,
                                 unsigned keep,
                                 unsigned lines_per_aperture)
    : gr::sync_block(
          "image_sink",
          gr::io_signature::make(
              1,
              1,
              sizeof(gr_complex) * check_at_least("num_range_bins", num_range_bins, 1u)),
          gr::io_signature::make(0, 0, 0)),
      d_K(num_range_bins),
      d_lines_param(lines_per_aperture),
      d_writer(
          make_config(prefix, write_npy, write_png, dynamic_range_db, colormap, keep)),
      d_port(pmt::mp("files"))
{
    message_port_register_out(d_port);
    d_expected = d_lines_param;
}

image_sink_impl::~image_sink_impl() {}

void image_sink_impl::start_aperture()
{
    d_lines = 0;
    d_expected = d_lines_param;
    d_have_index = false;
    d_azimuth_axis = pmt::PMT_NIL;
    d_nonfinite.rearm();
}

void image_sink_impl::flush(bool partial)
{
    if (d_lines == 0)
        return;
    const std::uint64_t n = d_have_index ? d_index : d_next_index;
    d_next_index = n + 1;
    std::vector<std::string> files;
    try {
        files = d_writer.write(d_buf.data(), d_lines, d_K, n);
    } catch (const std::exception& e) {
        d_logger->error("aperture {} not saved: {}", n, e.what());
    }
    if (partial)
        d_logger->info("aperture {}: partial, {} of {} lines written", n, d_lines, d_expected);
    if (!files.empty()) {
        ++d_written;
        d_last = files;
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::mp("aperture"), pmt::from_uint64(n));
        d = pmt::dict_add(d, pmt::mp("lines"), pmt::from_uint64(d_lines));
        d = pmt::dict_add(d, pmt::mp("range_bins"), pmt::from_uint64(d_K));
        d = pmt::dict_add(d, pmt::mp("partial"), pmt::from_bool(partial));
        for (const auto& f : files) {
            const bool npy = f.size() > 4 && f.compare(f.size() - 4, 4, ".npy") == 0;
            d = pmt::dict_add(d, pmt::mp(npy ? "npy" : "png"), pmt::mp(f));
        }
        if (!pmt::is_null(d_range_axis))
            d = pmt::dict_add(d, pmt::mp("range_axis"), d_range_axis);
        if (!pmt::is_null(d_azimuth_axis))
            d = pmt::dict_add(d, pmt::mp("azimuth_axis"), d_azimuth_axis);
        message_port_pub(d_port, d);
    }
    start_aperture();
}

void image_sink_impl::append(const gr_complex* lines, unsigned n, std::uint64_t first_item)
{
    while (n > 0) {
        const unsigned cap = d_expected > 0 ? d_expected : max_untagged_lines;
        const unsigned take = std::min(n, cap - d_lines);
        const size_t need = static_cast<size_t>(d_lines + take) * d_K;
        if (d_buf.size() < need)
            d_buf.resize(std::max(need, static_cast<size_t>(cap > 4096 ? 4096 : cap) * d_K));
        gr_complex* dst = &d_buf[static_cast<size_t>(d_lines) * d_K];
        const size_t count = static_cast<size_t>(take) * d_K;
        std::memcpy(dst, lines, sizeof(gr_complex) * count);
        std::uint64_t bad = 0, first_bad = 0;
        for (size_t j = 0; j < count; ++j) {
            if (!(std::isfinite(dst[j].real()) && std::isfinite(dst[j].imag()))) {
                dst[j] = gr_complex(0.0f, 0.0f);
                if (bad++ == 0)
                    first_bad = j;
            }
        }
        if (bad)
            d_nonfinite.note(d_logger, bad, first_item + first_bad / d_K);
        d_lines += take;
        lines += count;
        first_item += take;
        n -= take;
        if (d_lines == cap)
            flush(false);
    }
}

int image_sink_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star&)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    const std::uint64_t n0 = nitems_read(0);
    auto& tags = d_tags;
    get_tags_in_range(tags, 0, n0, n0 + noutput_items);
    sort_aperture_first(tags);
    std::uint64_t pos = n0;
    size_t t = 0;
    while (pos < n0 + noutput_items) {
        // Tags on line `pos` first (an aperture tag starts a new image there).
        for (; t < tags.size() && tags[t].offset <= pos; ++t) {
            const tag_t& tag = tags[t];
            if (pmt::eq(tag.key, tags::aperture_key())) {
                if (d_lines > 0)
                    flush(true);
                d_have_index = pmt::is_integer(tag.value) || pmt::is_uint64(tag.value);
                if (d_have_index)
                    d_index = pmt::to_uint64(tag.value);
            } else if (pmt::eq(tag.key, tags::azimuth_axis_key())) {
                const pmt::pmt_t& v = tag.value;
                std::uint64_t m = 0;
                if (parse_azimuth_lines(v, m)) {
                    if (m >= 1 && m <= (1u << 30) && m > d_lines) {
                        d_expected = static_cast<unsigned>(m);
                        d_azimuth_axis = v;
                    }
                } else {
                    d_logger->warn("ignoring malformed azimuth_axis tag {}", pmt::write_string(v));
                }
            } else if (pmt::eq(tag.key, tags::range_axis_key())) {
                d_range_axis = tag.value;
            }
        }
        const std::uint64_t end =
            t < tags.size() ? std::min<std::uint64_t>(tags[t].offset, n0 + noutput_items)
                            : n0 + noutput_items;
        append(in + static_cast<size_t>(pos - n0) * d_K, static_cast<unsigned>(end - pos), pos);
        pos = end;
    }
    return noutput_items;
}

bool image_sink_impl::stop()
{
    gr::thread::scoped_lock guard(d_setlock);
    // The end of the stream: the partial aperture is written as it is.
    flush(d_expected == 0 || d_lines < d_expected);
    return true;
}

void image_sink_impl::set_dynamic_range_db(double dynamic_range_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_writer.set_dynamic_range_db(dynamic_range_db);
}
double image_sink_impl::dynamic_range_db() const { return d_writer.config().dynamic_range_db; }
void image_sink_impl::set_colormap(image_colormap colormap)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_writer.set_colormap(colormap);
}
image_colormap image_sink_impl::colormap() const { return d_writer.config().colormap; }
std::uint64_t image_sink_impl::apertures_written() const { return d_written; }
std::vector<std::string> image_sink_impl::last_files() const
{
    gr::thread::scoped_lock guard(const_cast<image_sink_impl*>(this)->d_setlock);
    return d_last;
}
std::vector<std::string> image_sink_impl::kept_files() const
{
    gr::thread::scoped_lock guard(const_cast<image_sink_impl*>(this)->d_setlock);
    return d_writer.kept();
}
std::uint64_t image_sink_impl::nonfinite_count() const { return d_nonfinite.count(); }

} // namespace nrsar
} // namespace gr
