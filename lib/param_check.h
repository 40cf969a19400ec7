/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Parameter checks shared by every constructor and setter: each throws
// std::invalid_argument (Python: ValueError) naming the parameter, its value and the limit.

#ifndef INCLUDED_NRSAR_PARAM_CHECK_H
#define INCLUDED_NRSAR_PARAM_CHECK_H

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gr {
namespace nrsar {

template <typename T>
[[noreturn]] void throw_param(const std::string& name, T value, const std::string& limit)
{
    std::ostringstream msg;
    msg << name << " = " << value << " " << limit;
    throw std::invalid_argument(msg.str());
}

inline void check_finite(const std::string& name, double value)
{
    if (!std::isfinite(value))
        throw_param(name, value, "must be finite");
}

inline void check_finite_positive(const std::string& name, double value)
{
    if (!std::isfinite(value) || value <= 0.0)
        throw_param(name, value, "must be finite and > 0");
}

//! SNR of an echo generator: +inf turns the noise off, NaN and -inf are refused.
inline void check_snr_db(double snr_db)
{
    if (std::isnan(snr_db) || snr_db == -INFINITY)
        throw_param("snr_db", snr_db, "must be a number above -inf (+inf turns the noise off)");
}

//! Returns value, so member initialisers can validate in place.
template <typename T>
T check_at_least(const std::string& name, T value, T minimum)
{
    if (value < minimum) {
        std::ostringstream limit;
        limit << "must be at least " << minimum;
        throw_param(name, value, limit.str());
    }
    return value;
}

template <typename T>
void check_range(const std::string& name, T value, T lo, T hi)
{
    if (!(value >= lo && value <= hi)) {
        std::ostringstream limit;
        limit << "must be in [" << lo << ", " << hi << "]";
        throw_param(name, value, limit.str());
    }
}

//! A list of at most max_count points whose every coordinate is finite (name[i] names one).
template <typename Points>
void check_finite_points(const std::string& name, const Points& points, std::size_t max_count)
{
    if (points.size() > max_count)
        throw_param(
            name + " (count)", points.size(), "must be at most " + std::to_string(max_count));
    for (std::size_t i = 0; i < points.size(); ++i)
        for (double v : points[i])
            check_finite(name + "[" + std::to_string(i) + "]", v);
}

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PARAM_CHECK_H */
