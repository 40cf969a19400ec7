/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/split_worker.h>

namespace gr {
namespace nrsar {
namespace kernel {

split_worker::~split_worker() { stop(); }

void split_worker::loop()
{
    std::unique_lock<std::mutex> lock(d_mutex);
    for (;;) {
        d_cv.wait(lock, [this] { return d_job != nullptr || d_quit; });
        if (d_quit)
            return;
        const job& f = *d_job;
        const std::size_t begin = d_begin, end = d_end;
        lock.unlock();
        std::exception_ptr error;
        try {
            f(begin, end, 1);
        } catch (...) {
            error = std::current_exception();
        }
        lock.lock();
        d_error = error;
        d_job = nullptr;
        d_cv.notify_all();
    }
}

void split_worker::run(std::size_t n, const job& f)
{
    if (!d_thread.joinable()) {
        d_quit = false;
        d_thread = std::thread([this] { loop(); });
    }
    const std::size_t split = n / 2;
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        d_job = &f;
        d_begin = split;
        d_end = n;
    }
    d_cv.notify_all();
    std::exception_ptr mine;
    try {
        f(0, split, 0);
    } catch (...) {
        mine = std::current_exception();
    }
    std::unique_lock<std::mutex> lock(d_mutex);
    d_cv.wait(lock, [this] { return d_job == nullptr; }); // f's buffers live until here
    std::exception_ptr theirs = d_error;
    d_error = nullptr;
    lock.unlock();
    if (mine)
        std::rethrow_exception(mine);
    if (theirs)
        std::rethrow_exception(theirs);
}

void split_worker::stop()
{
    if (!d_thread.joinable())
        return;
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        d_quit = true;
    }
    d_cv.notify_all();
    d_thread.join();
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
