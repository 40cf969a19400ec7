/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "cheby_presum_impl.h"
#include "nonfinite_reporter.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/nrsar/tags.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {

cheby_presum::sptr cheby_presum::make(const numerology& num,
                                      const geometry& geo,
                                      const scene& scn,
                                      unsigned num_bins,
                                      double first_range_m,
                                      double range_bin_m,
                                      const kernel::presum_config& cfg,
                                      const trajectory& nav)
{
    return gnuradio::make_block_sptr<cheby_presum_impl>(
        kernel::cheby_presum(num, geo, scn, num_bins, first_range_m, range_bin_m, cfg, nav));
}

unsigned cheby_presum::max_decim(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 unsigned symbols_per_pulse)
{
    return kernel::cheby_presum::max_decim(num, geo, scn, symbols_per_pulse);
}

cheby_presum_impl::cheby_presum_impl(kernel::cheby_presum&& k)
    : gr::block("cheby_presum",
                gr::io_signature::make(1, 1, sizeof(gr_complex) * k.num_bins()),
                gr::io_signature::make(1, 1, sizeof(gr_complex) * k.num_bins())),
      d_kernel(std::move(k))
{
    set_tag_propagation_policy(TPP_DONT);
    for (const auto& w : d_kernel.warnings())
        d_logger->warn("{}", w);
}

void cheby_presum_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    // The kernel keeps its own window of L pulses, so any input is progress: asking for
    // the pulses that complete an output (up to L / 2 + 1 for the first) would stall on
    // large vectors, whose buffers hold only a few items ("requesting more input data
    // than we can provide").
    (void)noutput_items;
    ninput_items_required[0] = 1;
}

int cheby_presum_impl::general_work(int noutput_items,
                                    gr_vector_int& ninput_items,
                                    gr_vector_const_void_star& input_items,
                                    gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const unsigned k = d_kernel.num_bins();
    const std::uint64_t d = d_kernel.decim();
    const std::uint64_t base = nitems_read(0);
    const int nin = ninput_items[0];

    auto& tags = d_tags;
    get_tags_in_range(tags, 0, base, base + nin);
    std::sort(tags.begin(), tags.end(), gr::tag_t::offset_compare);
    std::size_t ti = 0;

    int consumed = 0, produced = 0;
    while (consumed < nin) {
        if (d_kernel.next_push_completes() && produced >= noutput_items)
            break;
        const std::uint64_t p = d_kernel.first_pulse() + base + consumed; // the flight's pulse
        const std::uint64_t group = p / d;
        for (; ti < tags.size() && tags[ti].offset == p; ++ti) {
            const auto& tag = tags[ti];
            if (pmt::eq(tag.key, tags::range_axis_key())) {
                if (pmt::is_tuple(tag.value) && pmt::length(tag.value) == 3 &&
                    pmt::to_uint64(pmt::tuple_ref(tag.value, 2)) == k) {
                    d_kernel.set_range_axis(pmt::to_double(pmt::tuple_ref(tag.value, 0)),
                                            pmt::to_double(pmt::tuple_ref(tag.value, 1)));
                    d_pending[group].push_back(tag);
                } else {
                    d_logger->warn("range_axis tag at item {} ignored (not (first, spacing, {}))",
                                   p,
                                   k);
                }
            } else if (pmt::eq(tag.key, tags::pulse_interval_key())) {
                const double t = pmt::to_double(tag.value);
                if (std::isfinite(t) && t > 0.0) {
                    d_kernel.set_pulse_interval(t);
                    gr::tag_t o = tag;
                    o.value = pmt::from_double(t * d);
                    d_pending[group].push_back(o);
                } else {
                    d_logger->warn("pulse_interval tag {} at item {} ignored", t, p);
                }
            } else if (p % d == 0) {
                d_pending[group].push_back(tag);
            }
        }
        std::size_t bad = 0;
        const gr_complex* x = d_guard.guard(in + static_cast<std::size_t>(consumed) * k, k, bad);
        if (bad) {
            d_pending_bad[group] += bad;
            d_nonfinite.note(d_logger, bad, p);
        }
        if (d_kernel.push(x, out + static_cast<std::size_t>(produced) * k)) {
            const std::uint64_t g = d_kernel.pulses_out() - 1;
            const std::uint64_t off = nitems_written(0) + produced;
            if (d_first) {
                add_item_tag(0,
                             off,
                             tags::pulse_interval_key(),
                             pmt::from_double(d_kernel.output_pulse_interval_s()),
                             alias_pmt());
                d_first = false;
                bool has_axis = false;
                for (const auto& [grp, v] : d_pending)
                    for (const auto& tag : v)
                        has_axis |= grp <= g && pmt::eq(tag.key, tags::range_axis_key());
                if (!has_axis && d_kernel.domain() == presum_domain::RANGE)
                    add_item_tag(0,
                                 off,
                                 tags::range_axis_key(),
                                 pmt::make_tuple(pmt::from_double(d_kernel.first_range_m()),
                                                 pmt::from_double(d_kernel.range_bin_m()),
                                                 pmt::from_uint64(k)),
                                 alias_pmt());
            }
            // Groups up to g are complete (later windows only add look-ahead).
            for (auto it = d_pending.begin(); it != d_pending.end() && it->first <= g;) {
                for (const auto& tag : it->second)
                    add_item_tag(0, off, tag.key, tag.value, alias_pmt());
                it = d_pending.erase(it);
            }
            std::uint64_t nbad = 0;
            for (auto it = d_pending_bad.begin(); it != d_pending_bad.end() && it->first <= g;) {
                nbad += it->second;
                it = d_pending_bad.erase(it);
            }
            if (nbad)
                add_item_tag(0, off, tags::nonfinite_key(), pmt::from_uint64(nbad), alias_pmt());
            ++produced;
        }
        ++consumed;
    }
    consume_each(consumed);
    return produced;
}

} // namespace nrsar
} // namespace gr
