/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_IMAGE_FILE_H
#define INCLUDED_NRSAR_KERNEL_IMAGE_FILE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

struct z_stream_s; // zlib's deflate state (zlib.h)

namespace gr {
namespace nrsar {

//! Colour map of the PNG pictures written by image_sink.
enum class image_colormap {
    GREY,   //!< 8-bit greyscale (PNG colour type 0): black = floor, white = peak
    VIRIDIS //!< matplotlib's viridis (PNG colour type 2, 8-bit RGB), as nrsar-sim's PNG
};

namespace kernel {

/*!
 * \brief The bytes of a NumPy .npy file (format 1.0) of a C-ordered complex64 array of
 * shape (rows, cols): magic, header dict {'descr': '<c8', 'fortran_order': False,
 * 'shape': (rows, cols)} padded to a multiple of 64 bytes, then the little-endian data.
 * numpy.load reads it back exactly (the layout nrsar-sim writes: azimuth x range).
 */
NRSAR_API std::string npy_header_complex64(size_t rows, size_t cols);

/*!
 * \brief Magnitude in dB re the peak, mapped to 8-bit levels:
 * level = round(255 (20 log10(|x| / max|x|) + dr) / dr), clipped to [0, 255]; 0 for x = 0
 * and for an all-zero image. Non-finite samples must have been replaced before (they give
 * level 0 here rather than spoiling the peak).
 */
NRSAR_API void db_levels(const gr_complex* data, size_t n, double dynamic_range_db, std::uint8_t* out);

//! 256-entry RGB table of a colour map (GREY: r = g = b = index).
NRSAR_API std::array<std::array<std::uint8_t, 3>, 256> colormap_table(image_colormap cmap);

/*!
 * \brief PNG (8-bit, no interlace, filter type 0 on every row) of width x height pixels:
 * channels 1 (greyscale, colour type 0) or 3 (RGB, colour type 2), row-major, top row
 * first. The image data are deflated by zlib at the given level (0..9).
 */
NRSAR_API std::vector<std::uint8_t> encode_png(const std::uint8_t* pixels,
                                               unsigned width,
                                               unsigned height,
                                               unsigned channels,
                                               int level = 6);

struct deflater_deleter {
    NRSAR_API void operator()(::z_stream_s* z) const;
};

//! What encode_png needs from one image to the next: buffers and zlib's state (about 270 kB).
struct png_buffers {
    std::unique_ptr<::z_stream_s, deflater_deleter> stream;
    int level = -1;
    std::vector<std::uint8_t> raw, z;
    std::vector<std::uint8_t> png; //!< the file
};

/*!
 * \brief encode_png into buf.png, reusing buf's buffers and deflate state: a writer of
 * images of one size allocates nothing after the first (a long stream's heap does not
 * fragment, docs/soak.md). The same bytes as encode_png.
 */
NRSAR_API void encode_png(const std::uint8_t* pixels,
                          unsigned width,
                          unsigned height,
                          unsigned channels,
                          int level,
                          png_buffers& buf);

//! What image_writer writes.
struct NRSAR_API image_file_config {
    std::string prefix;                         //!< files are <prefix>_<n>.npy / .png
    bool npy = true;                            //!< complex64 .npy, azimuth x range
    bool png = true;                            //!< dB picture
    double dynamic_range_db = 40.0;             //!< PNG: levels span [peak - dr, peak]
    image_colormap colormap = image_colormap::VIRIDIS;
    unsigned keep = 16; //!< files kept per format: older apertures' files are deleted
    //! zlib level of the PNG data (0..9). 1: a speckled SAR image deflates only 5 % better
    //! at 6 and takes 6x longer in viridis (bench_image_file).
    int png_level = 1;

    //! Throws std::invalid_argument: empty prefix, a folder that does not exist, is not a
    //! folder or is not writable, neither format, dr not finite and > 0, keep 0, level
    //! outside 0..9.
    void validate() const;
};

/*!
 * \brief Writes one image (azimuth x range, complex) per call as <prefix>_<n>.npy and/or
 * <prefix>_<n>.png, and deletes the files of the apertures older than the last `keep`
 * (a ring, so that an endless stream does not fill the disk).
 */
class NRSAR_API image_writer
{
public:
    explicit image_writer(const image_file_config& cfg);
    image_writer(const image_writer&) = delete;
    image_writer& operator=(const image_writer&) = delete;
    image_writer(image_writer&&) = default;
    image_writer& operator=(image_writer&&) = default;

    /*!
     * \brief Writes image number n (rows x cols, row-major); returns the paths written
     * (npy first). Throws std::runtime_error when a file cannot be written.
     */
    std::vector<std::string> write(const gr_complex* image, size_t rows, size_t cols, std::uint64_t n);

    const image_file_config& config() const { return d_cfg; }
    void set_dynamic_range_db(double dr);
    void set_colormap(image_colormap cmap);
    //! Path of file n with the given extension ("npy" or "png").
    std::string path(std::uint64_t n, const char* ext) const;
    //! Files currently kept (oldest first).
    std::vector<std::string> kept() const;

private:
    image_file_config d_cfg;
    std::array<std::array<std::uint8_t, 3>, 256> d_lut;
    std::vector<std::uint8_t> d_levels;
    std::vector<std::uint8_t> d_pixels;
    png_buffers d_png;
    std::deque<std::vector<std::string>> d_ring; // files of the kept apertures
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_IMAGE_FILE_H */
