/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::make_fft_fwd / make_fft_rev, the process's pool of gr::fft objects: a reused
// object computes what a fresh gr::fft plan computes, bit for bit, even after its last user
// left garbage in its buffers; handles held at once are distinct objects (each thread its
// own, results exact); a released object comes back for its own key only. Each test uses
// sizes of its own (the pool is the process's, and gtest may run them in one process).

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <gtest/gtest.h>
#include <atomic>
#include <cstring>
#include <random>
#include <set>
#include <thread>
#include <vector>

namespace kernel = gr::nrsar::kernel;

namespace {

std::vector<gr_complex> noise(std::size_t n, unsigned seed)
{
    std::mt19937 gen(seed);
    std::normal_distribution<float> g;
    std::vector<gr_complex> x(n);
    for (auto& v : x)
        v = gr_complex(g(gen), g(gen));
    return x;
}

// x through the FFT object f (in -> execute -> out)
template <class FFT>
std::vector<gr_complex> transform(FFT& f, const std::vector<gr_complex>& x)
{
    std::memcpy(f.get_inbuf(), x.data(), sizeof(gr_complex) * x.size());
    f.execute();
    return std::vector<gr_complex>(f.get_outbuf(), f.get_outbuf() + f.outbuf_length());
}

bool same_bits(const std::vector<gr_complex>& a, const std::vector<gr_complex>& b)
{
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(gr_complex) * a.size()) == 0;
}

} // namespace

TEST(fft_plans, reused_object_equals_a_fresh_plan_bit_for_bit)
{
    for (int n : { 1200, 3360, 625 }) {
        const auto x = noise(n, 7u + n);
        const gr_complex junk(3.0f, -5.0f);
        gr::fft::fft_complex_fwd* used;
        {
            auto f = kernel::make_fft_fwd(n);
            used = f.get();
            std::fill_n(f->get_inbuf(), n, junk); // what a previous kernel left behind
            f->execute();
        }
        auto f = kernel::make_fft_fwd(n);
        ASSERT_EQ(f.get(), used) << n; // the released object, not a new plan
        for (int i = 0; i < n; ++i) { // zero as a new object's
            ASSERT_EQ(f->get_inbuf()[i], gr_complex(0.0f, 0.0f)) << n << " in " << i;
            ASSERT_EQ(f->get_outbuf()[i], gr_complex(0.0f, 0.0f)) << n << " out " << i;
        }
        gr::fft::fft_complex_fwd fresh_fwd(n, 1);
        EXPECT_TRUE(same_bits(transform(*f, x), transform(fresh_fwd, x))) << n;

        {
            auto r = kernel::make_fft_rev(n);
            std::fill_n(r->get_inbuf(), n, junk);
            r->execute();
        }
        auto r = kernel::make_fft_rev(n);
        gr::fft::fft_complex_rev fresh_rev(n, 1);
        EXPECT_TRUE(same_bits(transform(*r, x), transform(fresh_rev, x))) << n;
    }
}

TEST(fft_plans, handles_held_at_once_are_distinct_and_exact)
{
    constexpr int n = 1536, threads = 6;
    gr::fft::fft_complex_rev fresh(n, 1);
    std::vector<std::vector<gr_complex>> inputs, expected;
    for (int t = 0; t < threads; ++t) {
        inputs.push_back(noise(n, 100u + t));
        expected.push_back(transform(fresh, inputs.back()));
    }
    std::vector<const void*> objects(threads);
    std::vector<std::vector<gr_complex>> outputs(threads);
    std::atomic<int> holding{ 0 };
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            auto f = kernel::make_fft_rev(n);
            objects[t] = f.get();
            ++holding;
            while (holding.load() < threads) // every thread holds its handle at once
                std::this_thread::yield();
            for (int rep = 0; rep < 20; ++rep) // each executes while the others do
                outputs[t] = transform(*f, inputs[t]);
        });
    for (auto& th : pool)
        th.join();
    EXPECT_EQ(std::set<const void*>(objects.begin(), objects.end()).size(), size_t(threads));
    for (int t = 0; t < threads; ++t)
        EXPECT_TRUE(same_bits(outputs[t], expected[t])) << "thread " << t;
    // all six are idle now: six takers get them back, a seventh a new one
    std::vector<kernel::fft_rev> again;
    for (int t = 0; t <= threads; ++t)
        again.push_back(kernel::make_fft_rev(n));
    std::set<const void*> back;
    for (int t = 0; t < threads; ++t)
        back.insert(again[t].get());
    EXPECT_EQ(back, std::set<const void*>(objects.begin(), objects.end()));
    EXPECT_EQ(back.count(again[threads].get()), 0u);
}

TEST(fft_plans, a_released_object_serves_its_own_key_only)
{
    constexpr int n = 720;
    const void* fwd;
    {
        auto f = kernel::make_fft_fwd(n);
        fwd = f.get();
    }
    {
        auto other_size = kernel::make_fft_fwd(2 * n);
        auto other_threads = kernel::make_fft_fwd(n, 2);
        EXPECT_NE(static_cast<const void*>(other_size.get()), fwd);
        EXPECT_NE(static_cast<const void*>(other_threads.get()), fwd);
        EXPECT_EQ(other_threads->nthreads(), 2);
        EXPECT_EQ(other_size->inbuf_length(), 2 * n);
        auto same = kernel::make_fft_fwd(n);
        EXPECT_EQ(static_cast<const void*>(same.get()), fwd);
        auto second = kernel::make_fft_fwd(n); // the first is still held: a new one
        EXPECT_NE(static_cast<const void*>(second.get()), fwd);
    }
    auto rev = kernel::make_fft_rev(n); // the other direction is another pool
    EXPECT_EQ(rev->inbuf_length(), n);
    EXPECT_NE(static_cast<const void*>(rev.get()), fwd);
}
