/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_MESSAGE_PORTS_H
#define INCLUDED_NRSAR_MESSAGE_PORTS_H

#include <pmt/pmt.h>

namespace gr {
namespace nrsar {

//! "pdus": the PDU port of nr_isac_tx and pusch_encoder (in) and pusch_receiver (out).
inline const pmt::pmt_t& pdus_port()
{
    static const pmt::pmt_t port = pmt::mp("pdus");
    return port;
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_MESSAGE_PORTS_H */
