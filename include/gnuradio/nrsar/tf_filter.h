/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TF_FILTER_H
#define INCLUDED_NRSAR_TF_FILTER_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/sync_block.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API tf_filter : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<tf_filter> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::tf_filter.
     *
     * To avoid accidental use of raw pointers, nrsar::tf_filter's
     * constructor is in a private implementation
     * class. nrsar::tf_filter::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TF_FILTER_H */
