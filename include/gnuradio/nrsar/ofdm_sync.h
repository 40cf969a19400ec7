/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_SYNC_H
#define INCLUDED_NRSAR_OFDM_SYNC_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API ofdm_sync : virtual public gr::block
{
public:
    typedef std::shared_ptr<ofdm_sync> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::ofdm_sync.
     *
     * To avoid accidental use of raw pointers, nrsar::ofdm_sync's
     * constructor is in a private implementation
     * class. nrsar::ofdm_sync::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_SYNC_H */
