/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_RANGE_IFFT_H
#define INCLUDED_NRSAR_RANGE_IFFT_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/sync_block.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API range_ifft : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<range_ifft> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::range_ifft.
     *
     * To avoid accidental use of raw pointers, nrsar::range_ifft's
     * constructor is in a private implementation
     * class. nrsar::range_ifft::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_RANGE_IFFT_H */
