/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Memory stays bounded on an endless stream (issue 16, docs/soak.md): what image_sink and
// nmse_probe do once per aperture allocates no image-sized buffer after the first aperture.
// Such buffers, allocated and freed every 2 s on different scheduler threads, fragmented
// glibc's per-thread arenas (RSS +0.3 MiB per radio second in a 240 s flight). This
// executable counts every heap allocation (malloc, calloc, realloc, posix_memalign,
// aligned_alloc, memalign: libstdc++'s operator new, VOLK and zlib all come through them)
// by interposing glibc's entry points; counts, not time or RSS, so the result is exact.

#include <gnuradio/nrsar/kernel/image_file.h>
#include <gnuradio/nrsar/kernel/image_metrics.h>
#include <gtest/gtest.h>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
}

namespace {

// Image-sized: glibc serves these by mmap until its dynamic threshold rises past them,
// then from the thread's arena, where they fragmented.
constexpr size_t large_bytes = 64 * 1024;
std::atomic<bool> counting{ false };
std::atomic<size_t> n_calls{ 0 }, n_large{ 0 };

void note(size_t n)
{
    if (counting.load(std::memory_order_relaxed)) {
        n_calls.fetch_add(1, std::memory_order_relaxed);
        if (n >= large_bytes)
            n_large.fetch_add(1, std::memory_order_relaxed);
    }
}

} // namespace

extern "C" {
void* malloc(size_t n)
{
    note(n);
    return __libc_malloc(n);
}
void* calloc(size_t a, size_t b)
{
    note(a * b);
    return __libc_calloc(a, b);
}
void* realloc(void* p, size_t n)
{
    note(n);
    return __libc_realloc(p, n);
}
void* memalign(size_t al, size_t n)
{
    note(n);
    return __libc_memalign(al, n);
}
void* aligned_alloc(size_t al, size_t n)
{
    note(n);
    return __libc_memalign(al, n);
}
int posix_memalign(void** p, size_t al, size_t n)
{
    if (al % sizeof(void*) != 0 || (al & (al - 1)) != 0)
        return EINVAL;
    note(n);
    void* q = __libc_memalign(al, n);
    if (!q)
        return ENOMEM;
    *p = q;
    return 0;
}
}

using namespace gr::nrsar;

namespace {

struct counts {
    size_t calls, large;
};

// Allocations made by f().
template <typename F>
counts count(F&& f)
{
    n_calls = 0;
    n_large = 0;
    counting = true;
    f();
    counting = false;
    return { n_calls.load(), n_large.load() };
}

// The sdr20 flight's focused aperture: 4800 lines x 35 range bins (docs/performance.md).
constexpr size_t lines = 4800, bins = 35;

std::vector<gr_complex> noisy_point_image(unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g;
    std::vector<gr_complex> img(lines * bins);
    for (auto& v : img)
        v = gr_complex(g(rng), g(rng));
    img[2400 * bins + 17] += gr_complex(300.0f, 0.0f);
    return img;
}

} // namespace

TEST(SteadyAlloc, CounterSeesEveryAllocator)
{
    // The interposition works: a vector, VOLK's aligned buffer and zlib's state are counted.
    const auto c = count([] {
        std::vector<float> v(large_bytes / sizeof(float));
        v[1] = 1.0f;
        volk::vector<float> w(large_bytes / sizeof(float));
        w[1] = v[1];
        std::vector<std::uint8_t> px(lines * bins, 7);
        kernel::encode_png(px.data(), bins, lines, 1, 6);
    });
    EXPECT_GE(c.large, 3u); // v, w and png's buffers (zlib's state: 5 more, 64-128 kB each)
}

TEST(SteadyAlloc, ImageWriterAllocatesNoImageBufferAfterTheFirstAperture)
{
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("nrsar_steady_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    kernel::image_file_config cfg;
    cfg.prefix = (dir / "image").string();
    cfg.colormap = image_colormap::VIRIDIS;
    cfg.keep = 2; // the ring deletes: the steady state of an endless stream
    kernel::image_writer w(cfg);
    const auto img = noisy_point_image(1);
    w.write(img.data(), lines, bins, 0); // the first aperture sizes the buffers
    // Apertures 1..8 and 9..16: no image-sized allocation, and about as many small ones
    // (file names, the ring) in the second half as in the first: nothing grows per aperture
    // (margin: one per aperture; the ring's deque takes a new node now and then).
    const auto first = count([&] {
        for (std::uint64_t n = 1; n <= 8; ++n)
            w.write(img.data(), lines, bins, n);
    });
    const auto second = count([&] {
        for (std::uint64_t n = 9; n <= 16; ++n)
            w.write(img.data(), lines, bins, n);
    });
    EXPECT_EQ(first.large, 0u);
    EXPECT_EQ(second.large, 0u);
    EXPECT_LE(second.calls, first.calls + 8);
    // The reused deflate state writes the bytes of a fresh encoder (new png_buffers).
    std::ifstream f(w.path(16, "png"), std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    std::vector<std::uint8_t> levels(lines * bins), rgb(3 * lines * bins);
    kernel::db_levels(img.data(), img.size(), cfg.dynamic_range_db, levels.data());
    const auto lut = kernel::colormap_table(cfg.colormap);
    for (size_t i = 0; i < levels.size(); ++i)
        for (int ch = 0; ch < 3; ++ch)
            rgb[3 * i + ch] = lut[levels[i]][ch];
    const auto fresh = kernel::encode_png(rgb.data(), bins, lines, 3, cfg.png_level);
    EXPECT_EQ(png, std::string(fresh.begin(), fresh.end()));
    fs::remove_all(dir);
}

TEST(SteadyAlloc, ImageMetricsAllocateNoImageBufferAfterTheFirstAperture)
{
    // nmse_probe's per-aperture work: the pixel weights and image_metrics::compute (whose
    // edge preservation index once allocated two lines x bins double images per call).
    const auto img = noisy_point_image(2), ref = noisy_point_image(3);
    kernel::image_metrics im;
    kernel::metrics_config cfg;
    cfg.range_res_bins = 1.0;
    cfg.azimuth_res_lines = 40.0;
    std::vector<float> weights;
    const auto aperture = [&](int n) {
        kernel::strip_pixel_weights_into(weights, lines, bins, n * 480.0, 0.1, 1000.0, 1.2,
                                         n * 480.0, n * 480.0 + 480.0, -40.0, 40.0, 0.06,
                                         30.0);
        return im.compute(img.data(), ref.data(), lines, bins, 2400, 17, cfg, nullptr, nullptr,
                          weights.data());
    };
    const double epi = aperture(0).epi;
    const auto first = count([&] {
        for (int n = 1; n <= 4; ++n)
            aperture(n);
    });
    const auto second = count([&] {
        for (int n = 5; n <= 8; ++n)
            aperture(n);
    });
    EXPECT_EQ(first.large, 0u);
    EXPECT_EQ(second.large, 0u);
    EXPECT_EQ(second.calls, first.calls);
    // The scratch version is the allocating one's index.
    EXPECT_EQ(epi, kernel::edge_preservation_index(ref.data(), img.data(), lines, bins));
}
