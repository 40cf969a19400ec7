/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_AUTOFOCUS_H
#define INCLUDED_NRSAR_AUTOFOCUS_H

#include <gnuradio/block.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/autofocus_config.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Autofocus of focused images: estimates the azimuth phase error the navigation did
 * not know (PGA or minimum entropy, kernel::autofocus) per aperture image, corrects the
 * image and passes it on.
 * \ingroup nrsar
 *
 * Input and output: one vector of K range bins per azimuth line (rd_focuser's and
 * bp_focuser's image output). An image starts at a tags::aperture_key() tag and holds M
 * lines, M from the tags::azimuth_axis_key() tag on the same line (else
 * cfg.lines_per_aperture); a new aperture tag before M lines, or the end of the stream,
 * closes the image as it is (at least 4 lines are corrected; shorter ones pass through).
 * Every input tag comes out on the same line of the corrected image (the block delays
 * the stream by one image). Message port "phase_error": per image a dict {aperture:
 * uint64, lines: uint64, iterations: uint64, phase_rms_rad, entropy_before,
 * entropy_after: double, phase_rad, weight: f64vector (M values, azimuth DFT order)}.
 * Non-finite input samples are zeroed and counted.
 */
class NRSAR_API autofocus : virtual public gr::block
{
public:
    typedef std::shared_ptr<autofocus> sptr;

    /*!
     * \param num_range_bins K, the vector length (>= 1)
     * \param cfg method and options (validated here)
     */
    static sptr make(unsigned num_range_bins, const autofocus_config& cfg = autofocus_config());

    virtual autofocus_config config() const = 0;
    //! Method from the next image on.
    virtual void set_method(autofocus_method method) = 0;
    //! Phase error estimated on the latest image [rad], azimuth DFT order (empty before).
    virtual std::vector<double> phase_error_rad() const = 0;
    //! Its energy-weighted rms [rad] (NaN before the first image).
    virtual double phase_rms_rad() const = 0;
    //! Image entropy of the latest image before and after the correction (NaN before).
    virtual double entropy_before() const = 0;
    virtual double entropy_after() const = 0;
    //! Images corrected so far.
    virtual std::uint64_t apertures() const = 0;
    //! Non-finite input samples zeroed so far.
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_AUTOFOCUS_H */
