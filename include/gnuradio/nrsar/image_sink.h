/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_IMAGE_SINK_H
#define INCLUDED_NRSAR_IMAGE_SINK_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/image_file.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

/*!
 * \brief Writes every focused aperture to files: <prefix>_<n>.npy (complex64, azimuth x
 * range, the layout nrsar-sim writes) and/or <prefix>_<n>.png (|x| in dB re the aperture's
 * peak over a dynamic range, greyscale or viridis; top row = first azimuth line).
 * \ingroup nrsar
 *
 * Input: one vector of K range bins per azimuth line (rd_focuser's image output). An
 * aperture starts at a tags::aperture_key() tag (its value is n) and holds M lines, M from
 * the tags::azimuth_axis_key() tag on the same line (else lines_per_aperture); it is
 * written as soon as its M lines are in. Without tags, apertures are lines_per_aperture
 * lines long and numbered 0, 1, ... (lines_per_aperture 0: one image of the whole stream,
 * at most 65536 lines each). A new aperture tag before M lines, or the end of the
 * stream, writes the partial aperture as it is. Files are written under a temporary name
 * and renamed (a viewer polling the folder never reads half a file). Only the files of the
 * last `keep` apertures stay on disk (a ring: older ones are deleted).
 * Message port "files": per aperture a dict {aperture: uint64, lines: uint64,
 * range_bins: uint64, partial: bool, npy: path, png: path (each when written),
 * range_axis, azimuth_axis: the tuples of the tags when they came}. The message of a
 * partial aperture written when the flowgraph stops may not reach its receiver (GNU Radio
 * ends message delivery then); the files are written.
 * Non-finite input samples are zeroed, counted (nonfinite_count()) and logged once per
 * aperture. A file that cannot be written is logged as an error and skipped.
 */
class NRSAR_API image_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<image_sink> sptr;

    /*!
     * \param num_range_bins K, the input vector length (>= 1)
     * \param prefix path prefix of the files, "folder/name" (the folder must exist and be
     *               writable; "name" alone writes into the working directory)
     * \param write_npy write <prefix>_<n>.npy (complex64, shape (M, K))
     * \param write_png write <prefix>_<n>.png (8-bit, M rows x K columns); at least one of
     *                  the two formats
     * \param dynamic_range_db PNG: levels span [peak - dynamic_range_db, peak] dB (> 0)
     * \param colormap PNG colour map (GREY or VIRIDIS)
     * \param keep apertures whose files are kept on disk (>= 1); older files are deleted
     * \param lines_per_aperture lines per image when no azimuth_axis tag says it (0: until
     *                           the next aperture tag or the end of the stream)
     */
    static sptr make(unsigned num_range_bins,
                     const std::string& prefix,
                     bool write_npy = true,
                     bool write_png = true,
                     double dynamic_range_db = 40.0,
                     image_colormap colormap = image_colormap::VIRIDIS,
                     unsigned keep = 16,
                     unsigned lines_per_aperture = 0);

    //! PNG dynamic range [dB], from the next image on.
    virtual void set_dynamic_range_db(double dynamic_range_db) = 0;
    virtual double dynamic_range_db() const = 0;
    //! PNG colour map, from the next image on.
    virtual void set_colormap(image_colormap colormap) = 0;
    virtual image_colormap colormap() const = 0;
    //! Apertures written so far (partial ones included).
    virtual std::uint64_t apertures_written() const = 0;
    //! Files written for the last aperture (npy first).
    virtual std::vector<std::string> last_files() const = 0;
    //! Files currently on disk (the ring), oldest first.
    virtual std::vector<std::string> kept_files() const = 0;
    //! Non-finite input samples zeroed so far.
    virtual std::uint64_t nonfinite_count() const = 0;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_IMAGE_SINK_H */
