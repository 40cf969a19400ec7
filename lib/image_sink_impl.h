/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_IMAGE_SINK_IMPL_H
#define INCLUDED_NRSAR_IMAGE_SINK_IMPL_H

#include <gnuradio/nrsar/image_sink.h>
#include <gnuradio/nrsar/kernel/image_file.h>
#include "nonfinite_reporter.h"
#include <volk/volk_alloc.hh>

namespace gr {
namespace nrsar {

class image_sink_impl : public image_sink
{
private:
    const unsigned d_K;
    const unsigned d_lines_param;
    kernel::image_writer d_writer;
    volk::vector<gr_complex> d_buf; // lines x K of the aperture being collected
    unsigned d_lines = 0;
    unsigned d_expected = 0;          // M of the current aperture (0: unknown)
    bool d_have_index = false;        // the current aperture came with an aperture tag
    std::uint64_t d_index = 0;        // its n
    std::uint64_t d_next_index = 0;   // n of an untagged aperture
    pmt::pmt_t d_range_axis = pmt::PMT_NIL;
    pmt::pmt_t d_azimuth_axis = pmt::PMT_NIL;
    std::uint64_t d_written = 0;
    std::vector<std::string> d_last;
    nonfinite_reporter d_nonfinite;
    std::vector<gr::tag_t> d_tags; // work()'s input tags (kept: no allocation per call)
    const pmt::pmt_t d_port;

    void append(const gr_complex* lines, unsigned n, std::uint64_t first_item);
    void flush(bool partial);
    void start_aperture();

public:
    image_sink_impl(unsigned num_range_bins,
                    const std::string& prefix,
                    bool write_npy,
                    bool write_png,
                    double dynamic_range_db,
                    image_colormap colormap,
                    unsigned keep,
                    unsigned lines_per_aperture);
    ~image_sink_impl() override;

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
    bool stop() override;

    void set_dynamic_range_db(double dynamic_range_db) override;
    double dynamic_range_db() const override;
    void set_colormap(image_colormap colormap) override;
    image_colormap colormap() const override;
    std::uint64_t apertures_written() const override;
    std::vector<std::string> last_files() const override;
    std::vector<std::string> kept_files() const override;
    std::uint64_t nonfinite_count() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_IMAGE_SINK_IMPL_H */
