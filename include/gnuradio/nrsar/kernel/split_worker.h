/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_SPLIT_WORKER_H
#define INCLUDED_NRSAR_KERNEL_SPLIT_WORKER_H

#include <gnuradio/nrsar/api.h>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The two-core split of the blocks with set_threads(2) (scene_echo, tf_filter,
 * range_ifft): one persistent second thread that takes the second half of a call's items.
 *
 * run(n, f) calls f(n / 2, n, 1) on the worker while the caller runs f(0, n / 2, 0), and
 * returns when both are done; each part writes only its own items' outputs, so the result
 * does not depend on the split. The thread starts at the first run() and is joined by
 * stop() or the destructor. An exception of either part is rethrown by run() after both
 * parts ended (the caller's first).
 */
class NRSAR_API split_worker
{
public:
    //! f(begin, end, part): items [begin, end), part 0 on the caller, 1 on the worker.
    using job = std::function<void(std::size_t begin, std::size_t end, unsigned part)>;

    split_worker() = default;
    split_worker(const split_worker&) = delete;
    split_worker& operator=(const split_worker&) = delete;
    ~split_worker();

    void run(std::size_t n, const job& f);
    //! Joins the thread (a later run() starts a new one).
    void stop();
    bool running() const { return d_thread.joinable(); }

private:
    std::thread d_thread;
    std::mutex d_mutex;
    std::condition_variable d_cv;
    const job* d_job = nullptr; // the pending job (nullptr: none)
    std::size_t d_begin = 0;
    std::size_t d_end = 0;
    std::exception_ptr d_error;
    bool d_quit = false;

    void loop();
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SPLIT_WORKER_H */
