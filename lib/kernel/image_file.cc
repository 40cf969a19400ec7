/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "param_check.h"
#include <gnuradio/nrsar/kernel/image_file.h>
#include <volk/volk.h>
#include <zlib.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {

void put_be32(std::vector<std::uint8_t>& v, std::uint32_t x)
{
    v.push_back(static_cast<std::uint8_t>(x >> 24));
    v.push_back(static_cast<std::uint8_t>(x >> 16));
    v.push_back(static_cast<std::uint8_t>(x >> 8));
    v.push_back(static_cast<std::uint8_t>(x));
}

// One PNG chunk: length, type, data, CRC-32 of type + data (zlib's crc32 is the PNG CRC).
void put_chunk(std::vector<std::uint8_t>& v, const char* type, const std::uint8_t* data, size_t n)
{
    put_be32(v, static_cast<std::uint32_t>(n));
    const size_t start = v.size();
    v.insert(v.end(), type, type + 4);
    if (n)
        v.insert(v.end(), data, data + n);
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), &v[start], static_cast<uInt>(4 + n));
    put_be32(v, static_cast<std::uint32_t>(crc));
}

// Writes to path + ".tmp" and renames, so that a reader polling the folder never sees a
// half-written file.
void write_file(const std::string& path, const void* a, size_t na, const void* b, size_t nb)
{
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f)
        throw std::runtime_error("image_sink: cannot open " + tmp + ": " + std::strerror(errno));
    const bool ok = std::fwrite(a, 1, na, f) == na && (nb == 0 || std::fwrite(b, 1, nb, f) == nb);
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) {
        std::remove(tmp.c_str());
        throw std::runtime_error("image_sink: cannot write " + path + " (disk full?)");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error("image_sink: cannot rename " + tmp + ": " + std::strerror(errno));
    }
}

// matplotlib's viridis (CC0) at entries 0, 8, ..., 248 and 255 of its 256-entry table,
// interpolated linearly: within 2 levels of the full table (checked in the QA against
// matplotlib itself), where a degree-6 polynomial fit was 4 levels off at the ends.
std::array<double, 3> viridis(double t)
{
    static const unsigned char c[33][3] = {
        { 68, 1, 84 },    { 71, 13, 96 },   { 72, 24, 106 },  { 72, 35, 116 },  { 71, 45, 123 },
        { 69, 55, 129 },  { 66, 64, 134 },  { 62, 73, 137 },  { 59, 82, 139 },  { 55, 91, 141 },
        { 51, 99, 141 },  { 47, 107, 142 }, { 44, 114, 142 }, { 41, 122, 142 }, { 38, 130, 142 },
        { 35, 137, 142 }, { 33, 145, 140 }, { 31, 152, 139 }, { 31, 160, 136 }, { 34, 167, 133 },
        { 40, 174, 128 }, { 50, 182, 122 }, { 63, 188, 115 }, { 78, 195, 107 }, { 94, 201, 98 },
        { 112, 207, 87 }, { 132, 212, 75 }, { 152, 216, 62 }, { 173, 220, 48 }, { 194, 223, 35 },
        { 216, 226, 25 }, { 236, 229, 27 }, { 253, 231, 37 },
    };
    const double x = std::clamp(t, 0.0, 1.0) * 255.0; // table index
    const int i = std::min(31, static_cast<int>(x / 8.0));
    const double x0 = 8.0 * i, x1 = (i == 31) ? 255.0 : 8.0 * (i + 1);
    const double w = (x - x0) / (x1 - x0);
    std::array<double, 3> rgb{};
    for (int ch = 0; ch < 3; ++ch)
        rgb[ch] = ((1.0 - w) * c[i][ch] + w * c[i + 1][ch]) / 255.0;
    return rgb;
}

} // namespace

std::string npy_header_complex64(size_t rows, size_t cols)
{
    std::string dict = "{'descr': '<c8', 'fortran_order': False, 'shape': (" +
                       std::to_string(rows) + ", " + std::to_string(cols) + "), }";
    // magic (6) + version (2) + header length (2) + dict + padding + '\n': a multiple of 64
    // so that the data are aligned (NumPy's own writer pads the same way).
    const size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict.push_back('\n');
    std::string h("\x93NUMPY\x01\x00", 8);
    const size_t len = dict.size();
    h.push_back(static_cast<char>(len & 0xff));
    h.push_back(static_cast<char>((len >> 8) & 0xff));
    return h + dict;
}

void db_levels(const gr_complex* data, size_t n, double dynamic_range_db, std::uint8_t* out)
{
    // |x|^2 in blocks on the stack, twice (peak, then levels): no image-sized buffer is
    // allocated per image, which fragmented a long stream's heap (docs/soak.md).
    constexpr size_t block = 1024;
    alignas(64) float p[block];
    float peak = 0.0f;
    for (size_t i0 = 0; i0 < n; i0 += block) {
        const size_t m = std::min(block, n - i0);
        volk_32fc_magnitude_squared_32f(p, data + i0, static_cast<unsigned>(m));
        for (size_t i = 0; i < m; ++i)
            if (p[i] > peak) // false for NaN
                peak = p[i];
    }
    if (!(peak > 0.0f) || !std::isfinite(peak)) {
        std::fill(out, out + n, std::uint8_t(0));
        return;
    }
    // level = 255 (10 log10(p / peak) + dr) / dr: one log per pixel, in float (the levels
    // are 0.16 dB apart at dr = 40 dB, far coarser than float's error).
    const float a = static_cast<float>(255.0 * 10.0 / dynamic_range_db);
    const float inv_peak = 1.0f / peak;
    for (size_t i0 = 0; i0 < n; i0 += block) {
        const size_t m = std::min(block, n - i0);
        volk_32fc_magnitude_squared_32f(p, data + i0, static_cast<unsigned>(m));
        for (size_t i = 0; i < m; ++i) {
            const float r = p[i] * inv_peak;
            float lv = r > 0.0f ? a * std::log10(r) + 255.0f : 0.0f;
            lv = std::min(255.0f, std::max(0.0f, lv)); // NaN -> 0 (max keeps the first operand)
            out[i0 + i] = static_cast<std::uint8_t>(std::lround(lv));
        }
    }
}

std::array<std::array<std::uint8_t, 3>, 256> colormap_table(image_colormap cmap)
{
    std::array<std::array<std::uint8_t, 3>, 256> lut{};
    for (int i = 0; i < 256; ++i) {
        if (cmap == image_colormap::GREY) {
            lut[i] = { static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i),
                       static_cast<std::uint8_t>(i) };
        } else {
            const auto rgb = viridis(i / 255.0);
            for (int ch = 0; ch < 3; ++ch)
                lut[i][ch] = static_cast<std::uint8_t>(
                    std::lround(255.0 * std::clamp(rgb[ch], 0.0, 1.0)));
        }
    }
    return lut;
}

void deflater_deleter::operator()(z_stream_s* z) const
{
    deflateEnd(z);
    delete z;
}

void encode_png(const std::uint8_t* pixels,
                unsigned width,
                unsigned height,
                unsigned channels,
                int level,
                png_buffers& buf)
{
    if (width == 0 || height == 0)
        throw_param("png width x height", static_cast<double>(width) * height, "must be > 0");
    if (channels != 1 && channels != 3)
        throw_param("png channels", channels, "must be 1 or 3");
    check_range("png_level", level, 0, 9);
    if (!buf.stream || buf.level != level) {
        auto z = std::make_unique<z_stream_s>();
        if (deflateInit(z.get(), level) != Z_OK) // compress2's settings
            throw std::runtime_error("image_sink: zlib deflateInit failed");
        buf.stream.reset(z.release());
        buf.level = level;
    } else if (deflateReset(buf.stream.get()) != Z_OK) {
        throw std::runtime_error("image_sink: zlib deflateReset failed");
    }
    std::vector<std::uint8_t>& out = buf.png;
    out.assign({ 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' });
    std::uint8_t ihdr[13];
    for (int i = 0; i < 4; ++i) {
        ihdr[i] = static_cast<std::uint8_t>(width >> (24 - 8 * i));
        ihdr[4 + i] = static_cast<std::uint8_t>(height >> (24 - 8 * i));
    }
    ihdr[8] = 8;                        // bit depth
    ihdr[9] = channels == 1 ? 0 : 2;    // colour type: grey / RGB
    ihdr[10] = ihdr[11] = ihdr[12] = 0; // deflate, filter method 0, no interlace
    put_chunk(out, "IHDR", ihdr, sizeof ihdr);

    // Raw scanlines, each led by its filter type byte (0: none).
    const size_t stride = static_cast<size_t>(width) * channels;
    buf.raw.resize((stride + 1) * height);
    for (unsigned y = 0; y < height; ++y) {
        buf.raw[y * (stride + 1)] = 0;
        std::memcpy(&buf.raw[y * (stride + 1) + 1], pixels + y * stride, stride);
    }
    z_stream_s& z = *buf.stream;
    buf.z.resize(deflateBound(&z, static_cast<uLong>(buf.raw.size())));
    z.next_in = buf.raw.data();
    z.avail_in = static_cast<uInt>(buf.raw.size());
    z.next_out = buf.z.data();
    z.avail_out = static_cast<uInt>(buf.z.size());
    if (deflate(&z, Z_FINISH) != Z_STREAM_END)
        throw std::runtime_error("image_sink: zlib deflate failed");
    put_chunk(out, "IDAT", buf.z.data(), z.total_out);
    put_chunk(out, "IEND", nullptr, 0);
}

std::vector<std::uint8_t> encode_png(const std::uint8_t* pixels,
                                     unsigned width,
                                     unsigned height,
                                     unsigned channels,
                                     int level)
{
    png_buffers buf;
    encode_png(pixels, width, height, channels, level, buf);
    return std::move(buf.png);
}

void image_file_config::validate() const
{
    if (prefix.empty())
        throw std::invalid_argument("prefix = '' must name a file prefix (folder/name)");
    namespace fs = std::filesystem;
    const fs::path parent = fs::path(prefix).parent_path();
    const std::string folder = parent.empty() ? std::string(".") : parent.string();
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw std::invalid_argument("prefix = '" + prefix + "': folder '" + folder +
                                    (fs::exists(folder, ec) ? "' is not a folder"
                                                            : "' does not exist"));
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        throw std::invalid_argument("prefix = '" + prefix + "': folder '" + folder +
                                    "' is not writable");
    if (fs::path(prefix).filename().empty())
        throw std::invalid_argument("prefix = '" + prefix + "' ends with a '/': add a file name");
    if (!npy && !png)
        throw std::invalid_argument("write_npy = false and write_png = false: nothing to write");
    if (!std::isfinite(dynamic_range_db) || dynamic_range_db <= 0.0)
        throw_param("dynamic_range_db", dynamic_range_db, "must be finite and > 0");
    check_at_least("keep", keep, 1u);
    check_range("png_level", png_level, 0, 9);
}

image_writer::image_writer(const image_file_config& cfg)
    : d_cfg(cfg), d_lut(colormap_table(cfg.colormap))
{
    d_cfg.validate();
}

void image_writer::set_dynamic_range_db(double dr)
{
    if (!std::isfinite(dr) || dr <= 0.0)
        throw_param("dynamic_range_db", dr, "must be finite and > 0");
    d_cfg.dynamic_range_db = dr;
}

void image_writer::set_colormap(image_colormap cmap)
{
    d_cfg.colormap = cmap;
    d_lut = colormap_table(cmap);
}

std::string image_writer::path(std::uint64_t n, const char* ext) const
{
    return d_cfg.prefix + "_" + std::to_string(n) + "." + ext;
}

std::vector<std::string> image_writer::kept() const
{
    std::vector<std::string> all;
    for (const auto& files : d_ring)
        all.insert(all.end(), files.begin(), files.end());
    return all;
}

std::vector<std::string>
image_writer::write(const gr_complex* image, size_t rows, size_t cols, std::uint64_t n)
{
    if (rows == 0 || cols == 0)
        throw_param("image rows x cols", static_cast<double>(rows) * cols, "must be > 0");
    std::vector<std::string> written;
    if (d_cfg.npy) {
        const std::string h = npy_header_complex64(rows, cols);
        const std::string p = path(n, "npy");
        // gr_complex is two little-endian float32 on every platform GNU Radio runs on.
        write_file(p, h.data(), h.size(), image, rows * cols * sizeof(gr_complex));
        written.push_back(p);
    }
    if (d_cfg.png) {
        const size_t count = rows * cols;
        d_levels.resize(count);
        db_levels(image, count, d_cfg.dynamic_range_db, d_levels.data());
        const bool grey = d_cfg.colormap == image_colormap::GREY;
        const std::uint8_t* px = d_levels.data();
        if (!grey) {
            d_pixels.resize(3 * count);
            for (size_t i = 0; i < count; ++i)
                std::memcpy(&d_pixels[3 * i], d_lut[d_levels[i]].data(), 3);
            px = d_pixels.data();
        }
        encode_png(px,
                   static_cast<unsigned>(cols),
                   static_cast<unsigned>(rows),
                   grey ? 1 : 3,
                   d_cfg.png_level,
                   d_png);
        const std::string p = path(n, "png");
        write_file(p, d_png.png.data(), d_png.png.size(), nullptr, 0);
        written.push_back(p);
    }
    // The ring: forget (and delete) the oldest aperture's files beyond `keep`. A name that
    // a newer aperture wrote again (a repeated index) is kept.
    d_ring.push_back(written);
    while (d_ring.size() > d_cfg.keep) {
        const std::vector<std::string> oldest = d_ring.front();
        d_ring.pop_front();
        for (const auto& old : oldest) {
            bool reused = false;
            for (const auto& files : d_ring)
                reused = reused || std::find(files.begin(), files.end(), old) != files.end();
            if (!reused)
                std::remove(old.c_str());
        }
    }
    return written;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
