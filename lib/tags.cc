/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/tags.h>

namespace gr {
namespace nrsar {
namespace tags {

#define NRSAR_DEFINE_KEY(fn, name)              \
    const pmt::pmt_t& fn()                      \
    {                                           \
        static const pmt::pmt_t key = pmt::mp(name); \
        return key;                             \
    }

NRSAR_DEFINE_KEY(symbol_key, "symbol")
NRSAR_DEFINE_KEY(slot_key, "slot")
NRSAR_DEFINE_KEY(frame_key, "frame")
NRSAR_DEFINE_KEY(range_axis_key, "range_axis")
NRSAR_DEFINE_KEY(ground_range_axis_key, "ground_range_axis")
NRSAR_DEFINE_KEY(nonfinite_key, "nonfinite")
NRSAR_DEFINE_KEY(aperture_key, "aperture")
NRSAR_DEFINE_KEY(azimuth_axis_key, "azimuth_axis")
NRSAR_DEFINE_KEY(pulse_interval_key, "pulse_interval")
NRSAR_DEFINE_KEY(doppler_axis_key, "doppler_axis")

// ofdm_sync
NRSAR_DEFINE_KEY(sync_key, "sync")
NRSAR_DEFINE_KEY(gap_key, "gap")

#undef NRSAR_DEFINE_KEY

} // namespace tags
} // namespace nrsar
} // namespace gr
