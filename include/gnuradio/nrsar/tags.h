/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TAGS_H
#define INCLUDED_NRSAR_TAGS_H

#include <gnuradio/nrsar/api.h>
#include <pmt/pmt.h>

namespace gr {
namespace nrsar {

/*!
 * \brief Stream tag and message keys used across the module (compare with pmt::eq).
 *
 * symbol_key, slot_key, frame_key: uint64 absolute indices, tagged by nr_isac_tx on the
 * first symbol of every slot (symbol, slot) and frame (frame).
 * range_axis_key: pmt tuple (first bin [m], bin spacing [m], number of bins), tagged by
 * range_ifft on its first output item and whenever the axis changes.
 * nonfinite_key: uint64 count of non-finite samples a block zeroed since the last tag.
 */
namespace tags {
NRSAR_API const pmt::pmt_t& symbol_key();
NRSAR_API const pmt::pmt_t& slot_key();
NRSAR_API const pmt::pmt_t& frame_key();
NRSAR_API const pmt::pmt_t& range_axis_key();
NRSAR_API const pmt::pmt_t& nonfinite_key();
} // namespace tags

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TAGS_H */
