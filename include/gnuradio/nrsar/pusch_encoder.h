/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_ENCODER_H
#define INCLUDED_NRSAR_PUSCH_ENCODER_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API pusch_encoder : virtual public gr::block
{
public:
    typedef std::shared_ptr<pusch_encoder> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::pusch_encoder.
     *
     * To avoid accidental use of raw pointers, nrsar::pusch_encoder's
     * constructor is in a private implementation
     * class. nrsar::pusch_encoder::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_ENCODER_H */
