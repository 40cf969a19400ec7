/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_OFDM_DEMOD_H
#define INCLUDED_NRSAR_OFDM_DEMOD_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API ofdm_demod : virtual public gr::block
{
public:
    typedef std::shared_ptr<ofdm_demod> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::ofdm_demod.
     *
     * To avoid accidental use of raw pointers, nrsar::ofdm_demod's
     * constructor is in a private implementation
     * class. nrsar::ofdm_demod::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_OFDM_DEMOD_H */
