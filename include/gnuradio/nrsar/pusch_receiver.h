/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_RECEIVER_H
#define INCLUDED_NRSAR_PUSCH_RECEIVER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API pusch_receiver : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_receiver> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::pusch_receiver.
     *
     * To avoid accidental use of raw pointers, nrsar::pusch_receiver's
     * constructor is in a private implementation
     * class. nrsar::pusch_receiver::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_RECEIVER_H */
