/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The small dense solve of the autofocus kernels (autofocus.cc's Legendre fit, real;
// bp_autofocus.cc's neighbouring GCPs' echoes, complex): one elimination for both.

#ifndef INCLUDED_NRSAR_KERNEL_SMALL_SOLVE_H
#define INCLUDED_NRSAR_KERNEL_SMALL_SOLVE_H

#include <cmath>
#include <complex>
#include <cstddef>
#include <utility>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * Solves the n x n system A x = b (row-major; A and b are overwritten) by Gaussian
 * elimination with partial pivoting, for n up to about 10. A pivot whose magnitude is at
 * most tol is skipped and its unknown set to 0; returns false when that happened.
 */
template <class T>
bool solve_small(std::vector<T>& A, std::vector<T>& b, std::size_t n, double tol, std::vector<T>& x)
{
    bool ok = true;
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t piv = c;
        for (std::size_t r = c + 1; r < n; ++r)
            if (std::abs(A[r * n + c]) > std::abs(A[piv * n + c]))
                piv = r;
        for (std::size_t j = 0; j < n; ++j)
            std::swap(A[c * n + j], A[piv * n + j]);
        std::swap(b[c], b[piv]);
        if (!(std::abs(A[c * n + c]) > tol)) {
            ok = false;
            continue;
        }
        for (std::size_t r = c + 1; r < n; ++r) {
            const T f = A[r * n + c] / A[c * n + c];
            for (std::size_t j = c; j < n; ++j)
                A[r * n + j] -= f * A[c * n + j];
            b[r] -= f * b[c];
        }
    }
    x.assign(n, T(0.0));
    for (std::size_t c = n; c-- > 0;) {
        T s = b[c];
        for (std::size_t j = c + 1; j < n; ++j)
            s -= A[c * n + j] * x[j];
        x[c] = std::abs(A[c * n + c]) > tol ? s / A[c * n + c] : T(0.0);
    }
    return ok;
}

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_SMALL_SOLVE_H */
