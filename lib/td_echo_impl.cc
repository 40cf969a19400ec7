/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "td_echo_impl.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace nrsar {

td_echo::sptr td_echo::make(const numerology& num,
                            const geometry& geo,
                            const scene& scn,
                            double snr_db,
                            std::uint64_t seed,
                            unsigned taps,
                            double kaiser_beta,
                            const kernel::antenna_beam& beam,
                            const trajectory& path)
{
    return gnuradio::make_block_sptr<td_echo_impl>(
        num, geo, scn, snr_db, seed, taps, kaiser_beta, beam, path);
}

td_echo_impl::td_echo_impl(const numerology& num,
                           const geometry& geo,
                           const scene& scn,
                           double snr_db,
                           std::uint64_t seed,
                           unsigned taps,
                           double kaiser_beta,
                           const kernel::antenna_beam& beam,
                           const trajectory& path)
    : gr::sync_block("td_echo",
                     gr::io_signature::make(1, 1, sizeof(gr_complex)),
                     gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_num(num),
      d_geo(geo),
      d_echo(num, geo, scn, taps, kaiser_beta, beam, path), // validates everything
      d_noise(seed)
{
    check_and_log(scn);
    // The unitary FFT of the demodulator maps a time-domain variance sigma^2 per sample to
    // sigma^2 per RE.
    d_noise.set_signal_power(d_echo.get_scene().total_rcs());
    d_noise.set_snr_db(snr_db);
    set_history(d_echo.history() + 1); // the delay line; zeros before the stream start
    if (d_echo.band_edge() >= 0.5)
        d_logger->warn("the numerology fills the whole FFT band (num_subcarriers = {} of "
                       "fft_size = {}): fractional delays of the band-edge subcarriers are "
                       "not representable at this sample rate; the echo is accurate only "
                       "well inside the band",
                       num.num_subcarriers,
                       num.fft_size);
}

void td_echo_impl::check_and_log(const scene& scn) const
{
    for (const auto& warning : check_scenario(d_num, d_geo, scn, d_echo.path()))
        d_logger->warn("{}", warning);
}

void td_echo_impl::set_snr_db(double snr_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_noise.set_snr_db(snr_db);
}

void td_echo_impl::set_scene(const scene& scn)
{
    scn.validate();
    check_and_log(scn);
    gr::thread::scoped_lock guard(d_setlock);
    d_echo.set_scene(scn);
    d_noise.set_signal_power(d_echo.get_scene().total_rcs());
}

scene td_echo_impl::get_scene() const { return d_echo.get_scene(); }

int td_echo_impl::work(int noutput_items,
                       gr_vector_const_void_star& input_items,
                       gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const std::size_t n = static_cast<std::size_t>(noutput_items);
    const std::size_t hist = d_echo.history();

    // input_items[0] starts hist samples before the current ones (set_history; the
    // scheduler fills the history with zeros at the stream start).
    const std::uint64_t k0 = nitems_read(0);
    std::size_t zeroed = 0;
    d_guard.guard(in + hist, n, zeroed);
    if (zeroed) {
        std::size_t first = 0, last = 0;
        for (std::size_t i = 0; i < n; i++) {
            if (!(std::isfinite(in[hist + i].real()) && std::isfinite(in[hist + i].imag()))) {
                if (!last)
                    first = i;
                last = i + 1;
            }
        }
        const std::uint64_t item = nitems_written(0) + first;
        add_item_tag(0, d_nonfinite.tag(d_logger, zeroed, item, k0 + first, alias_pmt()));
        d_bad_end = k0 + last; // the history holds non-finite samples until d_bad_end + hist
    }
    const gr_complex* x = in + hist;
    if (d_bad_end > 0 && d_bad_end + hist > k0) {
        // Rare path: a non-finite sample in this call or in the history it reads: filter a
        // zeroed copy of history + input.
        std::size_t in_window = 0;
        x = d_guard.guard(in, hist + n, in_window) + hist;
    }

    const std::uint64_t before = d_echo.dropped_paths();
    d_echo.process(k0, x, out, n, d_noise.generator(), d_noise.sigma());
    if (d_echo.dropped_paths() > before && !d_dropped_logged) {
        d_logger->warn("a target's delay exceeds one OFDM symbol ({} samples) at sample {}: "
                       "left out (see dropped_paths())",
                       d_echo.max_delay_samples(),
                       k0);
        d_dropped_logged = true;
    }
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
