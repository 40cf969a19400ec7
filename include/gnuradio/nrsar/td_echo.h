/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_TD_ECHO_H
#define INCLUDED_NRSAR_TD_ECHO_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/sync_block.h>

namespace gr {
namespace nrsar {

/*!
 * \brief <+description of block+>
 * \ingroup nrsar
 *
 */
class NRSAR_API td_echo : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<td_echo> sptr;

    /*!
     * \brief Return a shared_ptr to a new instance of nrsar::td_echo.
     *
     * To avoid accidental use of raw pointers, nrsar::td_echo's
     * constructor is in a private implementation
     * class. nrsar::td_echo::make is the public interface for
     * creating new instances.
     */
    static sptr make();
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_TD_ECHO_H */
