/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_AUTOFOCUS_IMPL_H
#define INCLUDED_NRSAR_AUTOFOCUS_IMPL_H

#include <gnuradio/nrsar/autofocus.h>
#include <gnuradio/nrsar/kernel/autofocus.h>
#include "nonfinite_reporter.h"
#include <volk/volk_alloc.hh>

namespace gr {
namespace nrsar {

class autofocus_impl : public autofocus
{
private:
    const unsigned d_K;
    kernel::autofocus d_kernel;
    kernel::image_axes d_axes;      // from the range_axis / azimuth_axis tags
    volk::vector<gr_complex> d_buf; // lines x K of the image being collected or sent
    unsigned d_fill = 0;            // lines collected
    unsigned d_expected = 0;        // M of the image being collected (0: unknown)
    std::uint64_t d_lines_in = 0;   // input lines taken (absolute)
    std::vector<tag_t> d_tags;      // its tags, offsets relative to its first line
    std::uint64_t d_index = 0;      // aperture of the image being collected
    // The corrected image being sent: lines [d_out_pos, d_out_len) still to go.
    unsigned d_out_pos = 0, d_out_len = 0;
    std::vector<tag_t> d_out_tags;
    bool d_flush_done = false;
    std::uint64_t d_apertures = 0;
    kernel::autofocus_result d_last;
    nonfinite_reporter d_nonfinite;
    const pmt::pmt_t d_port;

    void handle_tag(const tag_t& tag);
    void ingest(const gr_complex* in, unsigned n);
    void process_image();
    int drain(gr_complex* out, int noutput, int produced);

public:
    autofocus_impl(unsigned num_range_bins, const autofocus_config& cfg);
    ~autofocus_impl() override;

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

    autofocus_config config() const override;
    void set_method(autofocus_method method) override;
    std::vector<double> phase_error_rad() const override;
    double phase_rms_rad() const override;
    double entropy_before() const override;
    double entropy_after() const override;
    std::uint64_t apertures() const override;
    std::uint64_t nonfinite_count() const override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_AUTOFOCUS_IMPL_H */
