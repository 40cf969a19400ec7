/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "scene_echo_impl.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <cmath>

namespace gr {
namespace nrsar {

scene_echo::sptr scene_echo::make(const numerology& num,
                                  const geometry& geo,
                                  const scene& scn,
                                  double snr_db,
                                  std::uint64_t seed,
                                  const trajectory& path)
{
    return gnuradio::make_block_sptr<scene_echo_impl>(num, geo, scn, snr_db, seed, path);
}

scene_echo_impl::scene_echo_impl(const numerology& num,
                                 const geometry& geo,
                                 const scene& scn,
                                 double snr_db,
                                 std::uint64_t seed,
                                 const trajectory& path)
    : gr::sync_block(
          "scene_echo",
          gr::io_signature::make(1, 1, sizeof(gr_complex) * num.num_subcarriers),
          gr::io_signature::make(1, 2, sizeof(gr_complex) * num.num_subcarriers)),
      d_num(num),
      d_geo(geo),
      d_echo(num, geo, scn, path), // validates num, geo, scn and path
      d_echo2(num, geo, scn, path),
      d_noise(seed)
{
    check_and_log(scn);
    d_noise.set_signal_power(d_echo.get_scene().total_rcs());
    d_noise.set_snr_db(snr_db);
}

void scene_echo_impl::check_and_log(const scene& scn) const
{
    for (const auto& warning : check_scenario(d_num, d_geo, scn, d_echo.path()))
        d_logger->warn("{}", warning);
}

void scene_echo_impl::set_snr_db(double snr_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_noise.set_snr_db(snr_db);
}

double scene_echo_impl::snr_db() const { return d_noise.snr_db(); }

double scene_echo_impl::noise_variance() const { return d_noise.variance(); }

void scene_echo_impl::set_scene(const scene& scn)
{
    scn.validate();
    check_and_log(scn);
    gr::thread::scoped_lock guard(d_setlock);
    d_echo.set_scene(scn);
    d_echo2.set_scene(scn);
    d_noise.set_signal_power(d_echo.get_scene().total_rcs());
}

scene scene_echo_impl::get_scene() const { return d_echo.get_scene(); }

std::uint64_t scene_echo_impl::nonfinite_count() const { return d_nonfinite.count(); }

void scene_echo_impl::set_threads(unsigned threads)
{
    check_range("threads", threads, 1u, 2u);
    gr::thread::scoped_lock guard(d_setlock);
    d_threads = threads;
}

unsigned scene_echo_impl::threads() const { return d_threads; }

void scene_echo_impl::set_reference_only(bool on)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_reference_only = on;
}

bool scene_echo_impl::reference_only() const { return d_reference_only; }

bool scene_echo_impl::check_topology(int /*ninputs*/, int noutputs)
{
    if (d_reference_only && noutputs > 1)
        throw_param("noutputs", noutputs, "must be 1 with reference_only (out0 is the reference)");
    return true;
}

void scene_echo_impl::process(kernel::scene_echo& k,
                              const gr_complex* in,
                              gr_complex* out,
                              gr_complex* ref,
                              std::uint64_t m0,
                              int count,
                              std::size_t* bad)
{
    const std::size_t n = d_num.num_subcarriers;
    for (int i = 0; i < count; i++) {
        // eq. (7), (8) with the noise and the non-finite test in one pass; m is the
        // absolute slow-time index.
        bad[i] = k.echo(m0 + i,
                        in ? in + i * n : nullptr, // null: reference only (no Y, no noise)
                        out ? out + i * n : nullptr,
                        ref ? ref + i * n : nullptr,
                        d_noise.generator(),
                        d_noise.sigma());
    }
}

bool scene_echo_impl::stop()
{
    d_split.stop();
    return true;
}

scene_echo_impl::~scene_echo_impl() {}

int scene_echo_impl::work(int noutput_items,
                          gr_vector_const_void_star& input_items,
                          gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const std::size_t n = d_num.num_subcarriers;
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    auto* ref = output_items.size() > 1 ? static_cast<gr_complex*>(output_items[1]) : nullptr;
    if (d_reference_only) { // H into out0 (check_topology: no out1)
        ref = out;
        in = nullptr;
        out = nullptr;
    }
    const std::uint64_t m0 = nitems_read(0);
    d_bad.resize(noutput_items);

    if (d_threads > 1 && noutput_items >= 4) {
        d_split.run(noutput_items, [&](std::size_t begin, std::size_t end, unsigned p) {
            process(p == 0 ? d_echo : d_echo2,
                    in ? in + begin * n : nullptr,
                    out ? out + begin * n : nullptr,
                    ref ? ref + begin * n : nullptr,
                    m0 + begin,
                    static_cast<int>(end - begin),
                    d_bad.data() + begin);
        });
    } else {
        process(d_echo, in, out, ref, m0, noutput_items, d_bad.data());
    }

    for (int i = 0; i < noutput_items; i++) {
        const std::size_t bad = d_bad[i];
        if (!bad)
            continue;
        add_item_tag(0, d_nonfinite.tag(d_logger, bad, nitems_written(0) + i, m0 + i, alias_pmt()));
    }
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
