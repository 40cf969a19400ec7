/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TF_FILTER_IMPL_H
#define INCLUDED_NRSAR_TF_FILTER_IMPL_H

#include <gnuradio/nrsar/kernel/split_worker.h>
#include <gnuradio/nrsar/kernel/tf_filter.h>
#include <gnuradio/nrsar/tf_filter.h>
#include "nonfinite_reporter.h"
#include <memory>
#include <vector>

namespace gr {
namespace nrsar {

class tf_filter_impl : public tf_filter
{
private:
    kernel::tf_filter d_kernel;
    nonfinite_reporter d_nonfinite;
    std::vector<gr::tag_t> d_tags; // tags of input 0 in the current work() call
    // Two-core split (set_threads(2)): the second half of each work() call's items runs
    // on the split worker with this second kernel (settings mirrored from d_kernel).
    unsigned d_threads = 1;
    std::unique_ptr<kernel::tf_filter> d_helper;
    std::vector<std::size_t> d_bad; // non-finite count per item of the current call
    bool d_prepass = false;
    std::vector<float> d_sums; // the pre-pass's sums, four per item
    kernel::split_worker d_split; // last: joined before the kernels go

public:
    tf_filter_impl(unsigned vlen, gr::nrsar::filter_type type, double snr_db, bool estimate_snr);

    void set_filter_type(gr::nrsar::filter_type type) override;
    void set_snr_db(double snr_db) override;
    void set_estimate_snr(bool estimate) override;
    void set_constant_modulus_path(bool on) override;
    void set_snr_prepass(bool on) override;
    std::vector<float> snr_sums() const override;
    std::vector<double> snr_history() const override;
    void set_snr_history(const std::vector<double>& history) override;
    bool constant_modulus_path() const override;
    std::uint64_t constant_modulus_items() const override;
    void set_threads(unsigned threads) override;
    unsigned threads() const override { return d_threads; }

    gr::nrsar::filter_type filter_type() const override;
    double snr_db() const override;
    bool estimate_snr() const override;
    double estimated_snr_db() const override;
    std::uint64_t empty_re_count() const override;
    std::uint64_t nonfinite_count() const override;

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TF_FILTER_IMPL_H */
