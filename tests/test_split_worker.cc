/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// kernel::split_worker: the two parts cover [0, n) once, the second on another thread; one
// persistent thread over many calls; exceptions of either part reach the caller after both
// parts ended; stop() and a later run().

#include <gnuradio/nrsar/kernel/split_worker.h>
#include <gtest/gtest.h>
#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

using gr::nrsar::kernel::split_worker;

TEST(split_worker, parts_cover_every_item_once_the_second_on_the_worker)
{
    split_worker w;
    EXPECT_FALSE(w.running()); // no thread until the first run
    std::thread::id worker_id;
    for (std::size_t n : { 4u, 5u, 1000u, 1001u }) {
        std::vector<int> hits(n, 0);
        std::vector<unsigned> part_of(n, 9);
        std::thread::id ids[2];
        w.run(n, [&](std::size_t begin, std::size_t end, unsigned part) {
            ids[part] = std::this_thread::get_id();
            for (std::size_t i = begin; i < end; ++i) {
                ++hits[i];
                part_of[i] = part;
            }
        });
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_EQ(hits[i], 1) << "item " << i;
            EXPECT_EQ(part_of[i], i < n / 2 ? 0u : 1u) << "item " << i; // split at n / 2
        }
        EXPECT_EQ(ids[0], std::this_thread::get_id());
        EXPECT_NE(ids[1], std::this_thread::get_id());
        if (worker_id == std::thread::id())
            worker_id = ids[1];
        EXPECT_EQ(ids[1], worker_id); // persistent: the same thread every call
    }
    EXPECT_TRUE(w.running());
}

TEST(split_worker, returns_only_after_the_worker_part)
{
    split_worker w;
    for (int rep = 0; rep < 200; ++rep) {
        std::atomic<int> done{ 0 };
        w.run(8, [&](std::size_t, std::size_t, unsigned part) {
            if (part == 1)
                std::this_thread::yield();
            ++done;
        });
        ASSERT_EQ(done.load(), 2);
    }
}

TEST(split_worker, exceptions_of_either_part_reach_the_caller)
{
    split_worker w;
    std::atomic<int> ended{ 0 };
    auto throw_in = [&](unsigned bad) {
        return [&, bad](std::size_t, std::size_t, unsigned part) {
            ++ended;
            if (part == bad)
                throw std::runtime_error(bad == 0 ? "caller" : "worker");
        };
    };
    for (unsigned bad : { 0u, 1u }) {
        ended = 0;
        try {
            w.run(10, throw_in(bad));
            ADD_FAILURE() << "nothing thrown";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), bad == 0 ? "caller" : "worker");
        }
        EXPECT_EQ(ended.load(), 2); // both parts ran to their end before run() returned
    }
    // Still usable after an exception.
    std::vector<int> part_size(2, 0);
    w.run(6, [&](std::size_t b, std::size_t e, unsigned p) { part_size[p] = int(e - b); });
    EXPECT_EQ(part_size, std::vector<int>({ 3, 3 }));
}

TEST(split_worker, stop_joins_and_a_later_run_starts_again)
{
    split_worker w;
    std::vector<int> x(4, 0);
    auto job = [&](std::size_t b, std::size_t e, unsigned) {
        for (std::size_t i = b; i < e; ++i)
            ++x[i];
    };
    w.run(4, job);
    w.stop();
    EXPECT_FALSE(w.running());
    w.stop(); // twice is harmless
    w.run(4, job);
    EXPECT_TRUE(w.running());
    EXPECT_EQ(x, std::vector<int>(4, 2));
}
