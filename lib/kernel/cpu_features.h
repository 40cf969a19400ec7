/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_CPU_FEATURES_H
#define INCLUDED_NRSAR_KERNEL_CPU_FEATURES_H

namespace gr {
namespace nrsar {
namespace kernel {

//! Whether this CPU runs AVX2 (and FMA where asked): the run-time half of a SIMD path's
//! avx2_available(); the compile-time half is that translation unit's own #if.
inline bool cpu_supports_avx2(bool with_fma = false)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && (!with_fma || __builtin_cpu_supports("fma"));
}

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif
