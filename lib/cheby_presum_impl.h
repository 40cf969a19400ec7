/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_CHEBY_PRESUM_IMPL_H
#define INCLUDED_NRSAR_CHEBY_PRESUM_IMPL_H

#include <gnuradio/nrsar/cheby_presum.h>
#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/cheby_presum.h>
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <map>

namespace gr {
namespace nrsar {

class cheby_presum_impl : public cheby_presum
{
private:
    kernel::cheby_presum d_kernel;
    kernel::finite_guard d_guard;
    std::map<std::uint64_t, std::vector<gr::tag_t>> d_pending; // output group -> tags
    std::map<std::uint64_t, std::uint64_t> d_pending_bad;      // output group -> zeroed
    bool d_first = true;
    nonfinite_reporter d_nonfinite;
    std::vector<gr::tag_t> d_tags; // work()'s input tags (kept: no allocation per call)

public:
    cheby_presum_impl(kernel::cheby_presum&& k);

    unsigned decim() const override { return d_kernel.decim(); }
    presum_method method() const override { return d_kernel.method(); }
    presum_domain domain() const override { return d_kernel.domain(); }
    unsigned num_bins() const override { return d_kernel.num_bins(); }
    unsigned num_taps() const override { return d_kernel.num_taps(); }
    unsigned lookahead() const override { return d_kernel.lookahead(); }
    unsigned history() const override { return d_kernel.history(); }
    std::uint64_t first_pulse() const override { return d_kernel.first_pulse(); }
    double centre_offset() const override { return d_kernel.centre_offset(); }
    std::vector<gr_complex> taps() const override { return d_kernel.taps(); }
    std::vector<double> prototype() const override { return d_kernel.prototype(); }
    double passband_hz() const override { return d_kernel.passband_hz(); }
    bool equiripple() const override { return d_kernel.equiripple(); }
    double stopband_hz() const override { return d_kernel.stopband_hz(); }
    double passband_ripple_db() const override { return d_kernel.passband_ripple_db(); }
    double stopband_atten_db() const override { return d_kernel.stopband_atten_db(); }
    double doppler_centroid_hz() const override { return d_kernel.doppler_centroid_hz(); }
    double phase_frequency_hz(unsigned element) const override
    {
        return d_kernel.phase_frequency_hz(element);
    }
    double output_pulse_interval_s() const override
    {
        return d_kernel.output_pulse_interval_s();
    }
    double compensation_phase(unsigned element, double t_ref_s, double offset) const override
    {
        return d_kernel.compensation_phase(element, t_ref_s, offset);
    }
    std::vector<std::string> warnings() const override { return d_kernel.warnings(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }
    bool follows_path() const override { return d_kernel.follows_path(); }
    unsigned phase_segment() const override { return d_kernel.phase_segment(); }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_CHEBY_PRESUM_IMPL_H */
