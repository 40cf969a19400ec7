/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#include "extended_scene_echo_impl.h"
#include "param_check.h"
#include <gnuradio/io_signature.h>
#include <cmath>

namespace gr {
namespace nrsar {

namespace {

// The corners of every map's bounding box plus the point targets: what check_scenario
// needs to judge the farthest round trip, eta and the Doppler band.
scene bounding_scene(const scene& points, const std::vector<kernel::reflectivity_map>& maps)
{
    scene box = points;
    for (const auto& map : maps) {
        const double x1 = map.x0 + (map.nx - 1) * map.dx;
        const double y1 = map.y0 + (map.ny - 1) * map.dy;
        for (double x : { map.x0, x1 })
            for (double y : { map.y0, y1 })
                box.targets.emplace_back(x, y, 1.0);
    }
    return box;
}
} // namespace

extended_scene_echo::sptr extended_scene_echo::make(const numerology& num,
                                                    const geometry& geo,
                                                    const scene& points,
                                                    const std::vector<kernel::reflectivity_map>& maps,
                                                    const kernel::antenna_beam& beam,
                                                    double snr_db,
                                                    std::uint64_t seed,
                                                    unsigned taps,
                                                    double oversampling,
                                                    const trajectory& path)
{
    return gnuradio::make_block_sptr<extended_scene_echo_impl>(
        num, geo, points, maps, beam, snr_db, seed, taps, oversampling, path);
}

extended_scene_echo_impl::extended_scene_echo_impl(
    const numerology& num,
    const geometry& geo,
    const scene& points,
    const std::vector<kernel::reflectivity_map>& maps,
    const kernel::antenna_beam& beam,
    double snr_db,
    std::uint64_t seed,
    unsigned taps,
    double oversampling,
    const trajectory& path)
    : gr::sync_block(
          "extended_scene_echo",
          gr::io_signature::make(1, 1, sizeof(gr_complex) * num.num_subcarriers),
          gr::io_signature::make(1, 2, sizeof(gr_complex) * num.num_subcarriers)),
      d_num(num),
      d_gen(num, geo, points, maps, beam, taps, oversampling, path), // validates everything
      d_noise(seed)
{
    d_noise.set_snr_db(snr_db);
    const scene box = bounding_scene(points, maps);
    if (!box.targets.empty())
        for (const auto& warning : check_scenario(num, geo, box, path))
            d_logger->warn("{}", warning);
    d_noise.set_signal_power(d_gen.total_power());
}

void extended_scene_echo_impl::set_snr_db(double snr_db)
{
    gr::thread::scoped_lock guard(d_setlock);
    d_noise.set_snr_db(snr_db);
}

int extended_scene_echo_impl::work(int noutput_items,
                                   gr_vector_const_void_star& input_items,
                                   gr_vector_void_star& output_items)
{
    gr::thread::scoped_lock guard(d_setlock);
    const std::size_t n = d_num.num_subcarriers;
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    auto* ref = output_items.size() > 1 ? static_cast<gr_complex*>(output_items[1]) : nullptr;
    const std::uint64_t m0 = nitems_read(0);
    for (int i = 0; i < noutput_items; i++) {
        // eqs. (7), (8); m is the absolute slow-time index.
        const std::size_t bad = d_gen.echo(
            m0 + i, in + i * n, out + i * n, ref ? ref + i * n : nullptr, d_noise.generator(), d_noise.sigma());
        if (bad)
            add_item_tag(
                0, d_nonfinite.tag(d_logger, bad, nitems_written(0) + i, m0 + i, alias_pmt()));
    }
    return noutput_items;
}

} /* namespace nrsar */
} /* namespace gr */
