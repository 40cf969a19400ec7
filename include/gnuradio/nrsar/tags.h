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
 * aperture_key: uint64 aperture index, on the first line of every focused aperture.
 * azimuth_axis_key: pmt tuple (along-track position of the first line [m], line spacing [m],
 * number of lines), on the first line of every focused aperture.
 * pulse_interval_key: double, slow-time spacing of the pulses from here on [s] (presummers
 * tag their output with the new interval, Tsym * D).
 * doppler_axis_key: pmt tuple (Doppler of the first line [Hz], line spacing [Hz], number of
 * lines), on the first line of every range-Doppler map aperture (rd_focuser's rd_map port).
 */
namespace tags {
NRSAR_API const pmt::pmt_t& symbol_key();
NRSAR_API const pmt::pmt_t& slot_key();
NRSAR_API const pmt::pmt_t& frame_key();
NRSAR_API const pmt::pmt_t& range_axis_key();
//! bp_focuser on a ground grid: (x of column 0 [m], spacing [m], columns) instead of range_axis.
NRSAR_API const pmt::pmt_t& ground_range_axis_key();
NRSAR_API const pmt::pmt_t& nonfinite_key();
NRSAR_API const pmt::pmt_t& aperture_key();
NRSAR_API const pmt::pmt_t& azimuth_axis_key();
NRSAR_API const pmt::pmt_t& pulse_interval_key();
NRSAR_API const pmt::pmt_t& doppler_axis_key();

// ofdm_sync
//! "sync": dict ("cfo_hz" double, "timing" int64, "start" int64, "metric" double) that
//! ofdm_sync puts on output sample 0 of every acquisition.
NRSAR_API const pmt::pmt_t& sync_key();
//! "gap": uint64 samples lost, on the first of the zeros with which ofdm_sync completes the
//! symbol a gap (or a lost lock) cut; pusch_receiver reports the slot holding it lost.
NRSAR_API const pmt::pmt_t& gap_key();
} // namespace tags

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TAGS_H */
