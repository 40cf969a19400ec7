/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_MOD_IMPL_H
#define INCLUDED_NRSAR_OFDM_MOD_IMPL_H

#include "nonfinite_reporter.h"
#include <gnuradio/nrsar/kernel/finite_guard.h>
#include <gnuradio/nrsar/kernel/ofdm_modem.h>
#include <gnuradio/nrsar/ofdm_mod.h>

namespace gr {
namespace nrsar {

class ofdm_mod_impl : public ofdm_mod
{
private:
    kernel::ofdm_modulator d_kernel;
    kernel::finite_guard d_guard;
    nonfinite_reporter d_nonfinite;
    std::vector<gr::tag_t> d_tags; // this call's input tags (kept: no allocation per call)

public:
    explicit ofdm_mod_impl(kernel::ofdm_modulator&& kern);

    unsigned symbol_length() const override { return d_kernel.symbol_length(); }
    std::uint64_t nonfinite_count() const override { return d_nonfinite.count(); }

    int work(int noutput_items,
             gr_vector_const_void_star& input_items,
             gr_vector_void_star& output_items) override;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_MOD_IMPL_H */
