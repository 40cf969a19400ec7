/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_RANGE_COMPRESS_H
#define INCLUDED_NRSAR_KERNEL_RANGE_COMPRESS_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/range_ifft.h>
#include <gnuradio/nrsar/kernel/tf_filter.h>

namespace gr {
namespace nrsar {
namespace kernel {

/*!
 * \brief The per-RE filter of eq. (25) and the range compression of eq. (29) fused:
 * out = crop(IFFT(pad(w / sqrt(N) * y g(s)))) for one symbol.
 *
 * The filter's pass writes its product, times the window, straight into the transform's
 * zero-padded input (range_ifft::input()), so each symbol is read once and the filtered
 * symbol never leaves the cache; the transform and the crop follow. The result is
 * tf_filter::process followed by range_ifft::execute, with the same roundings in the same
 * order. Both parts stay reachable for their settings (filter(), ifft()).
 */
class NRSAR_API range_compress
{
public:
    //! filter.vlen() must equal ifft.n().
    range_compress(tf_filter&& filter, range_ifft&& ifft);
    range_compress(const range_compress&) = delete;
    range_compress& operator=(const range_compress&) = delete;
    range_compress(range_compress&&) = default;
    range_compress& operator=(range_compress&&) = default;

    /*!
     * Compresses one symbol: y (echo) and s (reference) of n() REs, out num_bins() bins.
     * Returns the non-finite input samples replaced by 0 (as tf_filter::process).
     */
    std::size_t process(const gr_complex* y, const gr_complex* s, gr_complex* out)
    {
        const std::size_t bad =
            d_filter.process(y, s, d_ifft.input(), d_ifft.window_taps2());
        d_ifft.transform(out);
        return bad;
    }

    tf_filter& filter() { return d_filter; }
    const tf_filter& filter() const { return d_filter; }
    range_ifft& ifft() { return d_ifft; }
    const range_ifft& ifft() const { return d_ifft; }
    unsigned n() const { return d_ifft.n(); }
    unsigned num_bins() const { return d_ifft.num_bins(); }

private:
    tf_filter d_filter;
    range_ifft d_ifft;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_RANGE_COMPRESS_H */
