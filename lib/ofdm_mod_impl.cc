/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "ofdm_mod_impl.h"
#include <gnuradio/io_signature.h>

namespace gr {
namespace nrsar {

ofdm_mod::sptr ofdm_mod::make(const numerology& num)
{
    num.validate();
    return gnuradio::make_block_sptr<ofdm_mod_impl>(kernel::ofdm_modulator(
        num.num_subcarriers, num.fft_size, num.cp_samples, num.dc_subcarrier()));
}

ofdm_mod_impl::ofdm_mod_impl(kernel::ofdm_modulator&& kern)
    : gr::sync_interpolator("ofdm_mod",
                            gr::io_signature::make(1, 1, sizeof(gr_complex) * kern.n()),
                            gr::io_signature::make(1, 1, sizeof(gr_complex)),
                            kern.symbol_length()),
      d_kernel(std::move(kern))
{
    // Tags are moved by hand (exactly to the symbol's first sample), not by the scheduler.
    set_tag_propagation_policy(TPP_DONT);
}

int ofdm_mod_impl::work(int noutput_items,
                        gr_vector_const_void_star& input_items,
                        gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto in = static_cast<const gr_complex*>(input_items[0]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t n = d_kernel.n();
    const std::uint64_t len = d_kernel.symbol_length();
    const int nsym = noutput_items / int(len);

    get_tags_in_range(d_tags, 0, nitems_read(0), nitems_read(0) + nsym);
    for (auto t : d_tags) {
        t.offset *= len; // the first sample (CP start) of the tagged symbol
        add_item_tag(0, t);
    }
    for (int i = 0; i < nsym; i++) {
        std::size_t bad = 0;
        const gr_complex* x = d_guard.guard(in + i * n, n, bad);
        d_kernel.execute(x, out + i * len);
        if (bad > 0) {
            const std::uint64_t symbol = nitems_read(0) + i;
            add_item_tag(0, d_nonfinite.tag(d_logger, bad, symbol * len, symbol, alias_pmt()));
        }
    }
    return nsym * int(len);
}

} // namespace nrsar
} // namespace gr
