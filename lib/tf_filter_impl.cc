/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "tf_filter_impl.h"
#include "nonfinite_reporter.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace gr {
namespace nrsar {

tf_filter::sptr
tf_filter::make(unsigned vlen, gr::nrsar::filter_type type, double snr_db, bool estimate_snr)
{
    // Checked here: the io signatures built from vlen would reject 0 with a vaguer message.
    check_at_least("vlen", vlen, 1u);
    return gnuradio::make_block_sptr<tf_filter_impl>(vlen, type, snr_db, estimate_snr);
}

std::vector<std::vector<double>> tf_filter::snr_histories(unsigned vlen,
                                                         const std::vector<float>& sums,
                                                         const std::vector<std::uint64_t>& items,
                                                         const std::vector<double>& history)
{
    check_at_least("vlen", vlen, 1u);
    if (sums.size() % 4 != 0)
        throw std::invalid_argument("sums: " + std::to_string(sums.size()) +
                                    " values, expected four per item");
    std::vector<kernel::snr_estimator::sums> all(sums.size() / 4);
    for (std::size_t i = 0; i < all.size(); i++)
        std::copy_n(sums.begin() + 4 * i, 4, all[i].begin());
    return kernel::snr_estimator::histories(all, vlen, items, history);
}

tf_filter_impl::tf_filter_impl(unsigned vlen,
                               gr::nrsar::filter_type type,
                               double snr_db,
                               bool estimate_snr)
    : gr::sync_block("tf_filter",
                     gr::io_signature::make(2, 2, sizeof(gr_complex) * vlen),
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * vlen)),
      d_kernel(vlen, type, snr_db, estimate_snr)
{
    // Both inputs usually descend from the same transmitter and carry the same tags (the
    // echo's and the reference grid's): the default ALL_TO_ALL would put each tag twice on
    // the output. The output is the echo filtered, so work() copies the tags of input 0
    // (ONE_TO_ONE needs as many outputs as inputs).
    set_tag_propagation_policy(TPP_CUSTOM);
}

void tf_filter_impl::set_filter_type(gr::nrsar::filter_type type)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_filter_type(type);
}

void tf_filter_impl::set_snr_db(double snr_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_snr_db(snr_db);
}

void tf_filter_impl::set_estimate_snr(bool estimate)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_estimate_snr(estimate);
}

void tf_filter_impl::set_snr_prepass(bool on)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_prepass = on;
}

std::vector<float> tf_filter_impl::snr_sums() const { return d_sums; }
std::vector<double> tf_filter_impl::snr_history() const { return d_kernel.snr_history(); }

void tf_filter_impl::set_snr_history(const std::vector<double>& history)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_snr_history(history);
}

void tf_filter_impl::set_constant_modulus_path(bool on)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_kernel.set_constant_modulus_path(on);
}

void tf_filter_impl::set_threads(unsigned threads)
{
    check_range("threads", threads, 1u, 2u);
    gr::thread::scoped_lock guard(d_setlock);
    d_threads = threads;
}

bool tf_filter_impl::constant_modulus_path() const { return d_kernel.constant_modulus_path(); }
std::uint64_t tf_filter_impl::constant_modulus_items() const
{
    return d_kernel.constant_modulus_vectors() +
           (d_helper ? d_helper->constant_modulus_vectors() : 0);
}

gr::nrsar::filter_type tf_filter_impl::filter_type() const { return d_kernel.type(); }
double tf_filter_impl::snr_db() const { return d_kernel.snr_db(); }
bool tf_filter_impl::estimate_snr() const { return d_kernel.estimate_snr(); }
double tf_filter_impl::estimated_snr_db() const { return d_kernel.estimated_snr_db(); }
std::uint64_t tf_filter_impl::empty_re_count() const
{
    return d_kernel.empty_re_count() + (d_helper ? d_helper->empty_re_count() : 0);
}
std::uint64_t tf_filter_impl::nonfinite_count() const { return d_nonfinite.count(); }

int tf_filter_impl::work(int noutput_items,
                         gr_vector_const_void_star& input_items,
                         gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto y = static_cast<const gr_complex*>(input_items[0]);
    const auto s = static_cast<const gr_complex*>(input_items[1]);
    auto out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t vlen = d_kernel.vlen();

    // 1:1 rate: a tag keeps its offset.
    d_tags.clear();
    get_tags_in_range(d_tags, 0, nitems_read(0), nitems_read(0) + noutput_items);
    for (const auto& tag : d_tags)
        add_item_tag(0, tag);

    d_bad.assign(noutput_items, 0);
    auto part = [&](std::size_t begin, std::size_t end, unsigned p) {
        auto& kern = p == 0 ? d_kernel : *d_helper;
        for (std::size_t i = begin; i < end; i++)
            d_bad[i] = kern.process(y + i * vlen, s + i * vlen, out + i * vlen);
    };
    if (d_prepass) {
        kernel::snr_estimator::sums v;
        for (int i = 0; i < noutput_items; i++) {
            d_bad[i] = d_kernel.snr_sums(y + i * vlen, s + i * vlen, v);
            d_sums.insert(d_sums.end(), v.begin(), v.end());
        }
        std::fill_n(out, std::size_t(noutput_items) * vlen, gr_complex(0, 0));
    } else if (d_threads == 2 && noutput_items >= 4 && !d_kernel.estimate_snr()) {
        // second kernel, same settings (WF's SNR_in as the first kernel uses it now)
        if (!d_helper)
            d_helper = std::make_unique<kernel::tf_filter>(
                unsigned(vlen), d_kernel.type(), d_kernel.effective_snr_db(), false);
        if (d_helper->type() != d_kernel.type())
            d_helper->set_filter_type(d_kernel.type());
        if (d_helper->snr_db() != d_kernel.effective_snr_db())
            d_helper->set_snr_db(d_kernel.effective_snr_db());
        d_helper->set_constant_modulus_path(d_kernel.constant_modulus_path());
        d_split.run(noutput_items, part);
    } else {
        part(0, noutput_items, 0);
    }
    for (int i = 0; i < noutput_items; i++) {
        const std::size_t bad = d_bad[i];
        if (bad > 0) {
            const std::uint64_t item = nitems_written(0) + i;
            add_item_tag(0, d_nonfinite.tag(d_logger, bad, item, item, alias_pmt()));
        }
    }
    return noutput_items;
}

} // namespace nrsar
} // namespace gr
