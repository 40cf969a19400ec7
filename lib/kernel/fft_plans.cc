/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include <gnuradio/nrsar/kernel/fft_plans.h>
#include <algorithm>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

namespace {

// Idle objects of one direction by (size, threads).
template <class FFT>
struct pool {
    std::mutex lock;
    std::map<std::pair<int, int>, std::vector<std::unique_ptr<FFT>>> idle;

    // Leaked on purpose: a kernel destroyed after static destruction still hands back.
    static pool& get()
    {
        static pool* p = new pool;
        return *p;
    }

    FFT* take(int size, int nthreads)
    {
        {
            std::lock_guard<std::mutex> guard(lock);
            auto& free = idle[{ size, nthreads }];
            if (!free.empty()) {
                FFT* fft = free.back().release();
                free.pop_back();
                // as a new object's (volk::vector value-initialises)
                std::fill_n(fft->get_inbuf(), fft->inbuf_length(), gr_complex(0.0f, 0.0f));
                std::fill_n(fft->get_outbuf(), fft->outbuf_length(), gr_complex(0.0f, 0.0f));
                return fft;
            }
        }
        // planned outside the pool's lock: gr::fft takes FFTW's planner mutex itself
        return new FFT(size, nthreads);
    }

    void give(FFT* fft) noexcept
    {
        std::unique_ptr<FFT> owned(fft);
        try {
            std::lock_guard<std::mutex> guard(lock);
            auto& free = idle[{ fft->inbuf_length(), fft->nthreads() }];
            if (free.size() < fft_pool_max_idle)
                free.push_back(std::move(owned));
        } catch (...) { // no memory for the list: the object is freed instead
        }
    }
};

} // namespace

void fft_release::operator()(gr::fft::fft_complex_fwd* fft) const noexcept
{
    pool<gr::fft::fft_complex_fwd>::get().give(fft);
}

void fft_release::operator()(gr::fft::fft_complex_rev* fft) const noexcept
{
    pool<gr::fft::fft_complex_rev>::get().give(fft);
}

fft_fwd make_fft_fwd(int size, int nthreads)
{
    return fft_fwd(pool<gr::fft::fft_complex_fwd>::get().take(size, nthreads));
}

fft_rev make_fft_rev(int size, int nthreads)
{
    return fft_rev(pool<gr::fft::fft_complex_rev>::get().take(size, nthreads));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr
