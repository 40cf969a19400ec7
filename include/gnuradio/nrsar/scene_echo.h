/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_SCENE_ECHO_H
#define INCLUDED_NRSAR_SCENE_ECHO_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/sync_block.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API scene_echo : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<scene_echo> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::scene_echo.
     *
     * To avoid accidental use of raw pointers, nrsar::scene_echo's
     * constructor is in a private implementation
     * class. nrsar::scene_echo::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_SCENE_ECHO_H */
