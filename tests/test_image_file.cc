/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::image_writer and its pieces: the .npy file read back byte for byte, the PNG
// decoded by a small reader written here (chunk CRCs, IHDR, inflate, filter bytes), the
// pixel levels against a double-precision dB computation, the ring of kept files.

#include <gnuradio/nrsar/kernel/image_file.h>
#include "test_util.h"
#include <gtest/gtest.h>
#include <zlib.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

using namespace gr::nrsar;
namespace fs = std::filesystem;

namespace {

std::string slurp(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::uint32_t be32(const std::string& s, size_t at)
{
    return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

struct png_image {
    unsigned width = 0, height = 0, channels = 0;
    std::vector<std::uint8_t> pixels;
};

// Minimal PNG reader: 8-bit grey or RGB, filter type 0 only (what the writer emits).
png_image decode_png(const std::string& s)
{
    const std::string sig("\x89PNG\r\n\x1a\n", 8);
    if (s.compare(0, 8, sig) != 0)
        throw std::runtime_error("bad signature");
    png_image img;
    std::string idat;
    size_t at = 8;
    bool end = false;
    while (!end) {
        const std::uint32_t len = be32(s, at);
        const std::string type = s.substr(at + 4, 4);
        const std::uint32_t crc = be32(s, at + 8 + len);
        const uLong want = crc32(0L, reinterpret_cast<const Bytef*>(&s[at + 4]), len + 4);
        if (crc != want)
            throw std::runtime_error("bad CRC in " + type);
        if (type == "IHDR") {
            img.width = be32(s, at + 8);
            img.height = be32(s, at + 12);
            if (s[at + 16] != 8 || s[at + 18] != 0 || s[at + 19] != 0 || s[at + 20] != 0)
                throw std::runtime_error("unsupported IHDR");
            img.channels = s[at + 17] == 0 ? 1 : (s[at + 17] == 2 ? 3 : 0);
        } else if (type == "IDAT") {
            idat += s.substr(at + 8, len);
        } else if (type == "IEND") {
            end = true;
        }
        at += 12 + len;
    }
    const size_t stride = static_cast<size_t>(img.width) * img.channels;
    std::vector<std::uint8_t> raw((stride + 1) * img.height);
    uLongf n = raw.size();
    if (uncompress(raw.data(), &n, reinterpret_cast<const Bytef*>(idat.data()), idat.size()) != Z_OK ||
        n != raw.size())
        throw std::runtime_error("inflate failed");
    for (unsigned y = 0; y < img.height; ++y) {
        if (raw[y * (stride + 1)] != 0)
            throw std::runtime_error("unexpected filter type");
        img.pixels.insert(img.pixels.end(),
                          raw.begin() + y * (stride + 1) + 1,
                          raw.begin() + (y + 1) * (stride + 1));
    }
    return img;
}

// The reference: 20 log10(|x| / max|x|) in double, mapped to 0..255.
std::vector<int> reference_levels(const std::vector<gr_complex>& x, double dr)
{
    double peak = 0.0;
    for (auto v : x)
        peak = std::max(peak, std::abs(std::complex<double>(v)));
    std::vector<int> lv(x.size(), 0);
    for (size_t i = 0; i < x.size(); ++i) {
        const double a = std::abs(std::complex<double>(x[i]));
        if (a == 0.0 || peak == 0.0)
            continue;
        const double db = 20.0 * std::log10(a / peak);
        lv[i] = static_cast<int>(std::lround(std::clamp(255.0 * (db + dr) / dr, 0.0, 255.0)));
    }
    return lv;
}

struct tmp_dir {
    fs::path path;
    tmp_dir()
    {
        path = fs::temp_directory_path() / ("nrsar_image_file_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~tmp_dir() { fs::remove_all(path); }
};

// The PNG alone of one lines x bins image written with c, decoded.
png_image written_png(const fs::path& dir,
                      kernel::image_file_config c,
                      const std::vector<gr_complex>& x,
                      size_t lines,
                      size_t bins)
{
    c.prefix = (dir / "p").string();
    c.npy = false;
    kernel::image_writer w(c);
    return decode_png(slurp(w.write(x.data(), lines, bins, 1).at(0)));
}

} // namespace

TEST(ImageFile, NpyHeaderIsNumpyFormat10)
{
    const std::string h = kernel::npy_header_complex64(37, 5);
    ASSERT_EQ(h.size() % 64, 0u);
    EXPECT_EQ(h.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const size_t len = std::uint8_t(h[8]) | (std::uint8_t(h[9]) << 8);
    EXPECT_EQ(len + 10, h.size());
    const std::string dict = h.substr(10);
    EXPECT_NE(dict.find("'descr': '<c8'"), std::string::npos);
    EXPECT_NE(dict.find("'fortran_order': False"), std::string::npos);
    EXPECT_NE(dict.find("'shape': (37, 5)"), std::string::npos);
    EXPECT_EQ(dict.back(), '\n');
}

TEST(ImageFile, NpyDataReadBack)
{
    tmp_dir d;
    kernel::image_file_config c;
    c.prefix = (d.path / "img").string();
    c.png = false;
    kernel::image_writer w(c);
    const auto x = nrsar_test::gaussian_samples(12 * 7, 3);
    const auto files = w.write(x.data(), 12, 7, 5);
    ASSERT_EQ(files.size(), 1u);
    EXPECT_EQ(files[0], c.prefix + "_5.npy");
    const std::string s = slurp(files[0]);
    const size_t hlen = 10 + (std::uint8_t(s[8]) | (std::uint8_t(s[9]) << 8));
    ASSERT_EQ(s.size(), hlen + x.size() * 8);
    EXPECT_EQ(std::memcmp(s.data() + hlen, x.data(), x.size() * 8), 0);
    EXPECT_FALSE(fs::exists(c.prefix + "_5.npy.tmp"));
}

TEST(ImageFile, LevelsMatchDoubleReference)
{
    auto x = nrsar_test::gaussian_samples(64 * 48, 11);
    x[100] = gr_complex(40.0f, -30.0f); // a target 30 dB above the clutter
    x[7] = gr_complex(0.0f, 0.0f);
    for (double dr : { 20.0, 40.0, 60.0 }) {
        std::vector<std::uint8_t> lv(x.size());
        kernel::db_levels(x.data(), x.size(), dr, lv.data());
        const auto ref = reference_levels(x, dr);
        size_t exact = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            ASSERT_LE(std::abs(int(lv[i]) - ref[i]), 1) << "pixel " << i << " dr " << dr;
            exact += lv[i] == ref[i];
        }
        EXPECT_GT(exact, x.size() * 99 / 100); // off by one only at rounding ties
        EXPECT_EQ(lv[100], 255);
        EXPECT_EQ(lv[7], 0);
    }
}

TEST(ImageFile, AllZeroImageIsBlack)
{
    std::vector<gr_complex> x(50, gr_complex(0.0f, 0.0f));
    std::vector<std::uint8_t> lv(x.size(), 9);
    kernel::db_levels(x.data(), x.size(), 40.0, lv.data());
    for (auto v : lv)
        EXPECT_EQ(v, 0);
}

TEST(ImageFile, GreyPngDecodesToLevels)
{
    tmp_dir d;
    kernel::image_file_config c;
    c.prefix = (d.path / "g").string();
    c.npy = false;
    c.colormap = image_colormap::GREY;
    c.dynamic_range_db = 30.0;
    kernel::image_writer w(c);
    auto x = nrsar_test::gaussian_samples(33 * 21, 5); // odd sizes: no stride luck
    x[5 * 21 + 3] *= 100.0f;
    const auto files = w.write(x.data(), 33, 21, 0);
    ASSERT_EQ(files.size(), 1u);
    const png_image img = decode_png(slurp(files[0]));
    EXPECT_EQ(img.width, 21u);
    EXPECT_EQ(img.height, 33u);
    EXPECT_EQ(img.channels, 1u);
    const auto ref = reference_levels(x, 30.0);
    ASSERT_EQ(img.pixels.size(), ref.size());
    for (size_t i = 0; i < ref.size(); ++i)
        ASSERT_LE(std::abs(int(img.pixels[i]) - ref[i]), 1) << i;
    EXPECT_EQ(img.pixels[5 * 21 + 3], 255); // row-major, top row = first line
}

TEST(ImageFile, ViridisPngMatchesMatplotlibsTable)
{
    // Entries of matplotlib's viridis table (matplotlib/_cm_listed.py, _viridis_data,
    // matplotlib 3.6.3; CC0), as 8-bit round(255 v): index, R, G, B.
    struct entry {
        int level, r, g, b;
    };
    const entry published[] = {
        { 0, 68, 1, 84 },      // 0.267004 0.004874 0.329415 (#440154)
        { 32, 71, 45, 123 },   // 0.278826 0.175490 0.483397
        { 64, 59, 82, 139 },   // 0.229739 0.322361 0.545706
        { 100, 42, 118, 142 }, // 0.166617 0.463708 0.558119
        { 128, 33, 145, 140 }, // 0.127568 0.566949 0.550556
        { 173, 58, 186, 118 }, // 0.226397 0.728888 0.462789
        { 192, 94, 201, 98 },  // 0.369214 0.788888 0.382914
        { 224, 173, 220, 48 }, // 0.678489 0.863742 0.189503
        { 255, 253, 231, 37 }, // 0.993248 0.906157 0.143936 (#fde725)
    };
    // One pixel per entry, its amplitude chosen so that 255 (20 log10 |x| + dr) / dr is the
    // entry's index exactly (peak 1 = 255), far from a rounding tie.
    const double dr = 40.0;
    std::vector<gr_complex> x;
    for (const auto& e : published)
        x.emplace_back(static_cast<float>(std::pow(10.0, (e.level * dr / 255.0 - dr) / 20.0)),
                       0.0f);
    tmp_dir d;
    kernel::image_file_config c;
    c.dynamic_range_db = dr;
    const png_image img = written_png(d.path, c, x, 1, x.size());
    ASSERT_EQ(img.channels, 3u);
    ASSERT_EQ(img.pixels.size(), 3 * x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const entry& e = published[i];
        // the writer interpolates the table between entries 0, 8, ..., 248, 255, documented
        // within 2 levels of the full table (exact at those entries)
        const int tol = (e.level % 8 == 0 || e.level == 255) ? 0 : 2;
        EXPECT_NEAR(img.pixels[3 * i], e.r, tol) << "level " << e.level;
        EXPECT_NEAR(img.pixels[3 * i + 1], e.g, tol) << "level " << e.level;
        EXPECT_NEAR(img.pixels[3 * i + 2], e.b, tol) << "level " << e.level;
    }
}

TEST(ImageFile, ViridisLuminanceRisesWithTheLevel)
{
    // viridis is built with monotonically increasing lightness, so on a clutter image the
    // decoded PNG's luminance must rise with the double-precision level of each pixel: the
    // brightest pixel of level L below the darkest of level L + 2 (the writer's float level
    // may round one step away from the reference at ties; its table is within 2 levels).
    tmp_dir d;
    const kernel::image_file_config c;
    const auto x = nrsar_test::gaussian_samples(64 * 48, 8);
    const png_image img = written_png(d.path, c, x, 64, 48);
    ASSERT_EQ(img.channels, 3u);
    const auto ref = reference_levels(x, c.dynamic_range_db);
    std::vector<double> lo(256, 1e9), hi(256, -1e9);
    for (size_t i = 0; i < x.size(); ++i) {
        // relative luminance of the sRGB-coded bytes (ITU-R BT.709 weights, linearised)
        auto lin = [](int v) {
            const double u = v / 255.0;
            return u <= 0.04045 ? u / 12.92 : std::pow((u + 0.055) / 1.055, 2.4);
        };
        const double y = 0.2126 * lin(img.pixels[3 * i]) + 0.7152 * lin(img.pixels[3 * i + 1]) +
                         0.0722 * lin(img.pixels[3 * i + 2]);
        lo[ref[i]] = std::min(lo[ref[i]], y);
        hi[ref[i]] = std::max(hi[ref[i]], y);
    }
    int pairs = 0;
    for (int l = 0; l + 2 < 256; ++l)
        if (hi[l] > -1e9 && lo[l + 2] < 1e9) {
            EXPECT_LT(hi[l], lo[l + 2]) << "level " << l;
            ++pairs;
        }
    EXPECT_GT(pairs, 150); // the clutter covers most of the 40 dB range
}

TEST(ImageFile, RingKeepsTheLastApertures)
{
    tmp_dir d;
    kernel::image_file_config c;
    c.prefix = (d.path / "r").string();
    c.keep = 2;
    kernel::image_writer w(c);
    const auto x = nrsar_test::gaussian_samples(4 * 4, 1);
    for (std::uint64_t n = 0; n < 5; ++n)
        w.write(x.data(), 4, 4, n);
    for (std::uint64_t n = 0; n < 5; ++n) {
        EXPECT_EQ(fs::exists(w.path(n, "npy")), n >= 3) << n;
        EXPECT_EQ(fs::exists(w.path(n, "png")), n >= 3) << n;
    }
    EXPECT_EQ(w.kept().size(), 4u);
    size_t files = std::distance(fs::directory_iterator(d.path), fs::directory_iterator());
    EXPECT_EQ(files, 4u);
    // A repeated index is rewritten, not deleted by the ring.
    w.write(x.data(), 4, 4, 4);
    w.write(x.data(), 4, 4, 4);
    EXPECT_TRUE(fs::exists(w.path(4, "npy")));
}

TEST(ImageFile, ConfigRules)
{
    tmp_dir d;
    auto bad = [&](auto edit, const char* fragment) {
        kernel::image_file_config c;
        c.prefix = (d.path / "x").string();
        edit(c);
        try {
            c.validate();
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    bad([](auto& c) { c.prefix = ""; }, "prefix = ''");
    bad([&](auto& c) { c.prefix = (d.path / "missing" / "x").string(); }, "does not exist");
    std::ofstream(d.path / "file").put('x');
    bad([&](auto& c) { c.prefix = (d.path / "file" / "x").string(); }, "is not a folder");
    bad([](auto& c) { c.dynamic_range_db = 0.0; }, "dynamic_range_db = 0");
    bad([](auto& c) { c.dynamic_range_db = NAN; }, "dynamic_range_db = nan");
    bad([](auto& c) { c.keep = 0; }, "keep = 0");
    bad([](auto& c) { c.npy = c.png = false; }, "nothing to write");
    bad([](auto& c) { c.png_level = 10; }, "png_level = 10");
}
