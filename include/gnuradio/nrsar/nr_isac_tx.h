/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_NR_ISAC_TX_H
#define INCLUDED_NRSAR_NR_ISAC_TX_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API nr_isac_tx : virtual public gr::block
{
public:
    typedef std::shared_ptr<nr_isac_tx> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::nr_isac_tx.
     *
     * To avoid accidental use of raw pointers, nrsar::nr_isac_tx's
     * constructor is in a private implementation
     * class. nrsar::nr_isac_tx::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_NR_ISAC_TX_H */
