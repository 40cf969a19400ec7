/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// The back-projection inner loops built with -mavx2 -mfma (lib/CMakeLists.txt); called only
// after avx2_available().

#include "bp_focuser_impl.h"

namespace gr {
namespace nrsar {
namespace kernel {
namespace bp_detail {

void project_line_avx2(const line_job& j) { project_line_body(j); }
void merge_line_avx2(const merge_job& m) { merge_line_body(m); }

} // namespace bp_detail
} // namespace kernel
} // namespace nrsar
} // namespace gr
