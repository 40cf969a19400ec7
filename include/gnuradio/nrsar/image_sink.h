/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_IMAGE_SINK_H
#define INCLUDED_NRSAR_IMAGE_SINK_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/sync_block.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API image_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<image_sink> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::image_sink.
     *
     * To avoid accidental use of raw pointers, nrsar::image_sink's
     * constructor is in a private implementation
     * class. nrsar::image_sink::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_IMAGE_SINK_H */
