/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Noisy QAM words of the NR LDPC code at rate 0.9, shared by test_nr_ldpc and bench_nr_ldpc.

#ifndef INCLUDED_NRSAR_TEST_NR_QAM_WORDS_H
#define INCLUDED_NRSAR_TEST_NR_QAM_WORDS_H

#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_rate_match.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <cmath>
#include <random>
#include <vector>

namespace nrsar_test {

/*!
 * BG1, Zc 384 (or the code block given: base graph, Zc, K' <= K with K - K' fillers) at rate
 * 0.9 on a QAM: random information bits, the codeword rate matched at rv 0 with the bit
 * interleaver of 38.212 5.4.2.2 (the first E / Qm bits of e on b(0) of the symbols, ...),
 * E = K' / 0.9 rounded down to Qm bits, the 38.211 constellation, complex AWGN of variance
 * N0 = 10^(-Es/N0 / 10), the module's max-log demapper and rate recovery (fillers +inf).
 */
class nr_qam_words
{
public:
    const int bg;
    const unsigned zc;

    nr_qam_words(gr::nrsar::modulation mod,
                 double esn0_db,
                 unsigned seed,
                 int base_graph = 1,
                 unsigned lift = 384,
                 unsigned k_prime = 0)
        : bg(base_graph), zc(lift), d_points(mod), d_demapper(mod), d_enc(bg, zc),
          d_n0(std::pow(10.0, -esn0_db / 10.0)), d_rng(seed),
          d_noise(0.0f, static_cast<float>(std::sqrt(d_n0 / 2))), d_d(d_enc.n())
    {
        const unsigned qm = d_points.bits_per_symbol();
        d_p.base_graph = bg;
        d_p.zc = zc;
        d_p.k_prime = k_prime > 0 ? k_prime : static_cast<unsigned>(d_enc.k());
        d_e = static_cast<std::size_t>(d_p.k_prime / 0.9) / qm * qm;
        d_p.qm = qm;
        d_f.resize(d_e);
        d_f_llr.resize(d_e);
        d_y.resize(d_e / qm);
    }

    //! Draws the next word: its K information bits (fillers 0) into c, the N LLRs of d into
    //! llr.
    void draw(std::vector<std::uint8_t>& c, std::vector<float>& llr)
    {
        namespace k = gr::nrsar::kernel;
        const unsigned qm = d_p.qm;
        c.resize(d_enc.k());
        llr.resize(d_enc.n());
        for (std::size_t k = 0; k < c.size(); k++)
            c[k] = k < d_p.k_prime ? d_rng() & 1u : 0u;
        d_enc.encode(c.data(), d_d.data());
        k::nr_rate_match(d_d.data(), d_p, d_e, d_f.data());
        for (std::size_t s = 0; s < d_y.size(); s++) {
            const float re = d_noise(d_rng), im = d_noise(d_rng);
            d_y[s] = d_points.map_bits(&d_f[s * qm]) + gr_complex(re, im);
        }
        d_demapper.demap(d_y.data(), static_cast<float>(d_n0), d_y.size(), d_f_llr.data());
        k::nr_rate_recover(d_f_llr.data(), d_p, d_e, llr.data(), false);
    }

private:
    gr::nrsar::kernel::constellation d_points;
    gr::nrsar::kernel::soft_demapper d_demapper;
    gr::nrsar::kernel::nr_ldpc_encoder d_enc;
    gr::nrsar::kernel::nr_rate_match_params d_p;
    double d_n0;
    std::mt19937 d_rng;
    std::normal_distribution<float> d_noise;
    std::size_t d_e = 0;
    std::vector<std::uint8_t> d_d, d_f;
    std::vector<float> d_f_llr;
    std::vector<gr_complex> d_y;
};

} // namespace nrsar_test

#endif /* INCLUDED_NRSAR_TEST_NR_QAM_WORDS_H */
