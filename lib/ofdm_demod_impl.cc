/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "ofdm_demod_impl.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>

namespace gr {
namespace nrsar {

ofdm_demod::sptr ofdm_demod::make(const numerology& num, int fft_start)
{
    num.validate();
    if (fft_start > int(num.cp_samples))
        throw_param("fft_start",
                    fft_start,
                    "must be at most cp_samples = " + std::to_string(num.cp_samples) +
                        " (a later FFT window reaches into the next symbol; < 0 means cp_samples)");
    const unsigned start = fft_start < 0 ? num.cp_samples : unsigned(fft_start);
    return gnuradio::make_block_sptr<ofdm_demod_impl>(kernel::ofdm_demodulator(
        num.num_subcarriers, num.fft_size, num.cp_samples, num.dc_subcarrier(), start));
}

ofdm_demod_impl::ofdm_demod_impl(kernel::ofdm_demodulator&& kern)
    : gr::sync_decimator("ofdm_demod",
                         gr::io_signature::make(1, 1, sizeof(gr_complex)),
                         gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.n()),
                         kern.symbol_length()),
      d_kernel(std::move(kern))
{
    // Tags are mapped by hand to the symbol they fall in (floor), not rounded.
    set_tag_propagation_policy(TPP_DONT);
}

int ofdm_demod_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t n = d_kernel.n();
    const std::uint64_t len = d_kernel.symbol_length();

    std::vector<gr::tag_t> tags;
    get_tags_in_range(tags, 0, nitems_read(0), nitems_read(0) + noutput_items * len);
    for (auto t : tags) {
        t.offset /= len;
        add_item_tag(0, t);
    }
    for (int i = 0; i < noutput_items; i++) {
        std::size_t bad = 0;
        const gr_complex* x = d_guard.guard(in + i * len, len, bad);
        d_kernel.execute(x, out + i * n);
        if (bad > 0) {
            const std::uint64_t item = nitems_written(0) + i;
            add_item_tag(0,
                         item,
                         tags::nonfinite_key(),
                         d_nonfinite.note(d_logger, bad, item),
                         alias_pmt());
        }
    }
    return noutput_items;
}

} // namespace nrsar
} // namespace gr
