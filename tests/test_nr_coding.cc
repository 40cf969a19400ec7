/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// CRC, code-block segmentation, rate matching and TBS of TS 38.212 / 38.214, each against
// a reference written here from the standard's text or worked by hand.

#include "test_util.h"
#include <gnuradio/nrsar/kernel/gold_sequence.h>
#include <gnuradio/nrsar/kernel/nr_crc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <gnuradio/nrsar/kernel/nr_ldpc_decoder.h>
#include <gnuradio/nrsar/kernel/nr_rate_match.h>
#include <gnuradio/nrsar/kernel/nr_segmentation.h>
#include <gnuradio/nrsar/kernel/nr_tbs.h>
#include <gnuradio/nrsar/kernel/nr_ulsch.h>
#include <gtest/gtest.h>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

using namespace gr::nrsar::kernel;

namespace {

// Polynomial long division of 38.212 5.1, bit by bit: remainder of a(D) D^L / g(D), g given
// by the exponents of its terms as the standard writes them.
std::vector<std::uint8_t> long_division(const std::vector<std::uint8_t>& a, const std::vector<unsigned>& g)
{
    const unsigned L = g.front();
    std::vector<std::uint8_t> buf(a);
    buf.resize(a.size() + L, 0);
    for (std::size_t i = 0; i < a.size(); i++)
        if (buf[i])
            for (unsigned e : g)
                buf[i + L - e] ^= 1u;
    return std::vector<std::uint8_t>(buf.end() - L, buf.end());
}

const std::vector<unsigned> g24a = { 24, 23, 18, 17, 14, 11, 10, 7, 6, 5, 4, 3, 1, 0 };
const std::vector<unsigned> g24b = { 24, 23, 6, 5, 1, 0 };
const std::vector<unsigned> g16 = { 16, 12, 5, 0 };

std::vector<std::uint8_t> ascii_bits(const std::string& s)
{
    std::vector<std::uint8_t> b;
    for (unsigned char ch : s)
        for (int k = 7; k >= 0; k--)
            b.push_back((ch >> k) & 1u);
    return b;
}

std::vector<std::uint8_t> random_bits(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> b(n);
    for (auto& v : b)
        v = rng() & 1u;
    return b;
}

} // namespace

TEST(NrCrc, MatchesLongDivisionOfTheStandardsPolynomials)
{
    const std::pair<nr_crc_type, const std::vector<unsigned>*> cases[] = {
        { nr_crc_type::crc24a, &g24a }, { nr_crc_type::crc24b, &g24b }, { nr_crc_type::crc16, &g16 }
    };
    for (const auto& [type, g] : cases) {
        const nr_crc crc(type);
        EXPECT_EQ(crc.length(), g->front());
        for (std::size_t n : { 0, 1, 7, 8, 9, 100, 1023, 3824 }) {
            const auto a = random_bits(n, static_cast<unsigned>(n) + crc.length());
            std::vector<std::uint8_t> out(n + crc.length());
            crc.attach(a.data(), n, out.data());
            const auto p = long_division(a, *g);
            EXPECT_TRUE(std::equal(p.begin(), p.end(), out.begin() + n)) << "L " << crc.length() << " n " << n;
            EXPECT_TRUE(crc.check(out.data(), out.size()));
            out[n / 2] ^= 1u;
            EXPECT_FALSE(crc.check(out.data(), out.size()));
        }
    }
}

TEST(NrCrc, PublishedCheckValues)
{
    // CRC catalogue (reveng.sourceforge.io, "123456789", init 0, no reflection, no xorout):
    // CRC-24/LTE-A = 0xCDE703, CRC-24/LTE-B = 0x23EF52, CRC-16/XMODEM (g16 of 38.212) = 0x31C3.
    const auto m = ascii_bits("123456789");
    EXPECT_EQ(nr_crc(nr_crc_type::crc24a).remainder(m.data(), m.size()), 0xCDE703u);
    EXPECT_EQ(nr_crc(nr_crc_type::crc24b).remainder(m.data(), m.size()), 0x23EF52u);
    EXPECT_EQ(nr_crc(nr_crc_type::crc16).remainder(m.data(), m.size()), 0x31C3u);
    EXPECT_EQ(nr_crc::parse("24A"), nr_crc_type::crc24a);
    EXPECT_NE(nrsar_test::error_of([] { nr_crc::parse("24C"); }).find("poly"), std::string::npos);
}

TEST(NrSegmentation, WorkedCases)
{
    struct wc {
        std::size_t B;
        int bg;
        unsigned C, K_prime, Zc, K, F;
    };
    // Worked from 5.2.2 by hand:
    const wc cases[] = {
        // B <= Kcb = 8448: C = 1, L = 0; 22 Zc >= 8448 -> Zc = 384
        { 8448, 1, 1, 8448, 384, 8448, 0 },
        // C = ceil(8450 / 8424) = 2, B' = 8498, K' = 4249; 22 Zc >= 4249 -> 208 (192 too small)
        { 8450, 1, 2, 4249, 208, 4576, 327 },
        // TB 25104 + CRC24A: C = ceil(25128 / 8424) = 3, B' = 25200, K' = 8400 -> 384, F = 48
        { 25128, 1, 3, 8400, 384, 8448, 48 },
        // BG1 1000 bits: 22 Zc >= 1000 -> 48 (44 too small)
        { 1000, 1, 1, 1000, 48, 1056, 56 },
        // BG2: Kcb = 3840; B = 3840: Kb = 10, Zc = 384
        { 3840, 2, 1, 3840, 384, 3840, 0 },
        // C = ceil(3842 / 3816) = 2, B' = 3890, K' = 1945, Kb = 10: Zc >= 194.5 -> 208
        { 3842, 2, 2, 1945, 208, 2080, 135 },
        // B = 600: Kb = 9, 9 Zc >= 600 -> 72 (64 too small); K = 10 Zc
        { 600, 2, 1, 600, 72, 720, 120 },
        // B = 200: Kb = 8, 8 Zc >= 200 -> 26 (24 too small)
        { 200, 2, 1, 200, 26, 260, 60 },
        // B = 100: Kb = 6, 6 Zc >= 100 -> 18 (16 too small)
        { 100, 2, 1, 100, 18, 180, 80 },
    };
    for (const wc& w : cases) {
        const auto s = nr_segmentation::compute(w.B, w.bg);
        EXPECT_EQ(s.C, w.C) << w.B;
        EXPECT_EQ(s.K_prime, w.K_prime) << w.B;
        EXPECT_EQ(s.Zc, w.Zc) << w.B;
        EXPECT_EQ(s.K, w.K) << w.B;
        EXPECT_EQ(s.F, w.F) << w.B;
        EXPECT_EQ(s.L, w.C > 1 ? 24u : 0u);
    }
}

TEST(NrSegmentation, EveryTbsOfBothGraphsFollowsTheText)
{
    // TBS values of 38.214 (table part and formula part), each + its TB CRC as B; the 5.2.2
    // text evaluated here: Zc scanned over a 2^j of Table 5.3.2-1.
    // The base graph is the one 6.2.2 selects, since 38.214 sizes a TB for its own graph
    // (with C > 1 under BG2 only for R <= 1/4, where the TBS formula uses 3816).
    std::vector<std::pair<std::size_t, int>> tbs_values;
    for (const auto table : { nr_mcs_table::qam64, nr_mcs_table::qam256 })
        for (unsigned n_prb = 1; n_prb <= 273; n_prb += 8)
            for (unsigned mcs = 0; mcs <= 27; mcs += 3) {
                const std::size_t A = nr_tbs(table, mcs, n_prb, 12, 12);
                tbs_values.push_back({ A, nr_select_base_graph(A, nr_mcs(table, mcs).code_rate()) });
            }
    std::size_t count[3] = {};
    for (const auto& [A, bg] : tbs_values) {
        count[bg]++;
        {
            const std::size_t B = A + (A > 3824 ? 24 : 16);
            const std::size_t Kcb = bg == 1 ? 8448 : 3840;
            const unsigned C = B <= Kcb ? 1 : static_cast<unsigned>(std::ceil(double(B) / (Kcb - 24)));
            const std::size_t Bp = C == 1 ? B : B + 24 * C;
            const std::size_t Kp = Bp / C;
            const unsigned Kb = bg == 1 ? 22 : (B > 640 ? 10 : B > 560 ? 9 : B > 192 ? 8 : 6);
            unsigned Zc = 1000;
            for (unsigned a : { 2, 3, 5, 7, 9, 11, 13, 15 })
                for (unsigned z = a; z <= 384; z *= 2)
                    if (Kb * z >= Kp && z < Zc)
                        Zc = z;
            const auto s = nr_segmentation::compute(B, bg);
            ASSERT_EQ(Bp % C, 0u) << "TBS " << A;
            EXPECT_EQ(s.C, C) << "TBS " << A << " BG" << bg;
            EXPECT_EQ(s.K_prime, Kp) << "TBS " << A;
            EXPECT_EQ(s.Zc, Zc) << "TBS " << A;
            EXPECT_EQ(s.K, (bg == 1 ? 22 : 10) * Zc);
            EXPECT_EQ(s.F, s.K - Kp);
        }
    }
    EXPECT_GT(count[1], 100u);
    EXPECT_GT(count[2], 100u);
}

TEST(NrSegmentation, BitsCrc24bAndFillers)
{
    const std::size_t B = 25128;
    const auto s = nr_segmentation::compute(B, 1);
    const auto b = random_bits(B, 4);
    std::vector<std::uint8_t> cb(std::size_t{ s.C } * s.K);
    nr_segment(b.data(), s, cb.data(), 7);
    for (unsigned r = 0; r < s.C; r++) {
        const std::size_t data = s.K_prime - 24;
        const std::uint8_t* c = cb.data() + r * s.K;
        EXPECT_TRUE(std::equal(c, c + data, b.begin() + r * data));
        const std::vector<std::uint8_t> a(c, c + data);
        const auto p = long_division(a, g24b);
        EXPECT_TRUE(std::equal(p.begin(), p.end(), c + data));
        for (std::size_t k = s.K_prime; k < s.K; k++)
            EXPECT_EQ(c[k], 7);
    }
    std::vector<std::uint8_t> back(B);
    std::vector<char> ok(s.C);
    bool oks[3];
    EXPECT_TRUE(nr_desegment(cb.data(), s, back.data(), oks));
    EXPECT_EQ(back, b);
    cb[s.K + 5] ^= 1u; // block 1 broken
    EXPECT_FALSE(nr_desegment(cb.data(), s, back.data(), oks));
    EXPECT_TRUE(oks[0]);
    EXPECT_FALSE(oks[1]);
    EXPECT_TRUE(oks[2]);
}

TEST(NrSegmentation, BaseGraphSelection)
{
    // 38.212 6.2.2: BG2 if A <= 292, or A <= 3824 and R <= 0.67, or R <= 0.25.
    EXPECT_EQ(nr_select_base_graph(292, 0.95), 2);
    EXPECT_EQ(nr_select_base_graph(293, 0.95), 1);
    EXPECT_EQ(nr_select_base_graph(3824, 0.67), 2);
    EXPECT_EQ(nr_select_base_graph(3824, 0.68), 1);
    EXPECT_EQ(nr_select_base_graph(3825, 0.5), 1);
    EXPECT_EQ(nr_select_base_graph(100000, 0.25), 2);
    EXPECT_EQ(nr_tb_crc_length(3824), 16u);
    EXPECT_EQ(nr_tb_crc_length(3825), 24u);
    EXPECT_NE(nrsar_test::error_of([] { nr_select_base_graph(100, 1.2); }).find("code_rate"), std::string::npos);
}

namespace {

// 38.212 5.4.2.1 and 5.4.2.2 from the text: positions of the circular buffer that e_k reads,
// then f_{i + j Qm} = e_{i E/Qm + j}.
std::vector<std::size_t> reference_positions(int bg, unsigned zc, unsigned kp, std::size_t ncb, unsigned rv, std::size_t E, unsigned qm)
{
    const double n_base = bg == 1 ? 66.0 : 50.0;
    const double num[2][4] = { { 0, 17, 33, 56 }, { 0, 13, 25, 43 } };
    const std::size_t k0 = static_cast<std::size_t>(std::floor(num[bg - 1][rv] * ncb / (n_base * zc))) * zc;
    const std::size_t K = (bg == 1 ? 22 : 10) * zc;
    std::vector<std::size_t> e;
    for (std::size_t j = 0; e.size() < E; j++) {
        const std::size_t p = (k0 + j) % ncb;
        const bool filler = p >= kp - 2 * zc && p < K - 2 * zc;
        if (!filler)
            e.push_back(p);
    }
    std::vector<std::size_t> f(E);
    for (std::size_t j = 0; j < E / qm; j++)
        for (unsigned i = 0; i < qm; i++)
            f[i + j * qm] = e[i * (E / qm) + j];
    return f;
}

nr_rate_match_params
rm_params(int bg, unsigned zc, unsigned kp, std::size_t n_ref, unsigned qm, unsigned rv = 0)
{
    nr_rate_match_params p;
    p.base_graph = bg;
    p.zc = zc;
    p.k_prime = kp;
    p.n_ref = n_ref;
    p.qm = qm;
    p.rv = rv;
    return p;
}

} // namespace

TEST(NrRateMatch, PositionsOfEveryRv)
{
    struct rc {
        int bg;
        unsigned zc, kp;
        std::size_t n_ref, E;
        unsigned qm;
    };
    const rc cases[] = {
        { 1, 384, 8400, 0, 9336, 8 },      // rate 0.9
        { 1, 208, 4249, 0, 30000, 6 },     // E > N_cb: the buffer wraps
        { 1, 384, 8448, 18000, 12000, 4 }, // limited buffer N_cb = 18000
        { 2, 72, 600, 0, 1200, 2 },
        { 2, 26, 200, 900, 2000, 4 },      // limited buffer and wrap
        { 2, 384, 3840, 0, 5000, 1 },
        { 1, 64, 1000, 0, 0, 2 },          // nothing sent
        { 1, 64, 1000, 2000, 24, 8 },      // a few bits, limited buffer
    };
    for (const rc& c : cases)
        for (unsigned rv = 0; rv < 4; rv++) {
            const nr_rate_match_params p = rm_params(c.bg, c.zc, c.kp, c.n_ref, c.qm, rv);
            const std::size_t N = nr_ldpc_n(c.bg, c.zc);
            const std::size_t ncb = c.n_ref ? std::min(N, c.n_ref) : N;
            EXPECT_EQ(p.n_cb(), ncb);
            const auto ref = reference_positions(c.bg, c.zc, c.kp, ncb, rv, c.E, c.qm);
            // bits: d with a random pattern, f must equal d at the reference positions
            const auto d = random_bits(N, rv + c.zc);
            std::vector<std::uint8_t> f(c.E);
            nr_rate_match(d.data(), p, c.E, f.data());
            std::size_t mismatches = 0;
            for (std::size_t k = 0; k < c.E; k++)
                mismatches += f[k] != d[ref[k]];
            EXPECT_EQ(mismatches, 0u) << "BG" << c.bg << " Zc " << c.zc << " rv " << rv;
            // soft: each f LLR lands on (and adds to) its reference position
            std::vector<float> llr(c.E), acc(N, 0.0f), want(N, 0.0f);
            for (std::size_t k = 0; k < c.E; k++) {
                llr[k] = static_cast<float>(k % 97) + 1.0f;
                want[ref[k]] += llr[k];
            }
            nr_rate_recover(llr.data(), p, c.E, acc.data());
            // a first transmission into an uninitialised buffer (combine = false)
            std::vector<float> fresh(N, NAN);
            nr_rate_recover(llr.data(), p, c.E, fresh.data(), false);
            for (std::size_t k = 0; k < N; k++) {
                const bool filler = k >= c.kp - 2 * c.zc && k < nr_ldpc_k(c.bg, c.zc) - 2 * c.zc;
                if (filler) {
                    EXPECT_EQ(acc[k], INFINITY);
                    EXPECT_EQ(fresh[k], INFINITY);
                } else {
                    ASSERT_EQ(acc[k], want[k]) << "position " << k << " rv " << rv;
                    ASSERT_EQ(fresh[k], want[k]) << "fresh buffer, position " << k << " rv " << rv;
                }
            }
        }
}

TEST(NrRateMatch, HarqCombiningAddsRedundancyVersions)
{
    nr_rate_match_params p = rm_params(1, 384, 8448, 0, 2);
    const std::size_t N = p.n(), E = 10000;
    std::vector<float> llr0(E, 1.0f), llr2(E, 2.0f), acc(N, 0.0f);
    p.rv = 0;
    nr_rate_recover(llr0.data(), p, E, acc.data());
    p.rv = 2;
    nr_rate_recover(llr2.data(), p, E, acc.data());
    const auto r0 = reference_positions(1, 384, 8448, N, 0, E, 2);
    const auto r2 = reference_positions(1, 384, 8448, N, 2, E, 2);
    std::vector<float> want(N, 0.0f);
    for (std::size_t k = 0; k < E; k++) {
        want[r0[k]] += 1.0f;
        want[r2[k]] += 2.0f;
    }
    EXPECT_EQ(acc, want);
    // rv 2 starts at k0 = floor(33 N / (66 Zc)) Zc = 33 Zc (Table 5.4.2.1-2 with N_cb = N).
    EXPECT_EQ(p.k0(), 33u * 384);
}

TEST(NrRateMatch, ColumnRecordClearsOnlyWhatMayBeNonZero)
{
    // A receiver's soft buffer across transport blocks with nr_rate_recover's column record
    // (nonzero_columns): after each call it holds the sum of the reference positions' LLRs
    // of the transmissions since the last new TB, exactly; every unflagged column is all
    // 0; and the decoder told the record decodes the same bits as the decoder reading it all.
    struct tx {
        unsigned rv;
        std::size_t E;
        bool combine;
    };
    struct rc {
        int bg;
        unsigned zc, kp;
        std::size_t n_ref;
        unsigned qm;
        std::vector<tx> seq;
    };
    const rc cases[] = {
        // wraps, then a short new TB whose unread columns held the first one's LLRs,
        // HARQ on it, nothing sent, the same rv and E twice (nothing left to clear)
        { 1, 384, 8400, 0, 8,
          { { 0, 30000, false }, { 2, 9336, false }, { 3, 2000, true }, { 1, 0, false },
            { 0, 9336, false }, { 0, 9336, false }, { 3, 4000, false } } },
        { 2, 26, 200, 900, 4,
          { { 2, 2000, false }, { 0, 100, false }, { 1, 300, true }, { 3, 40, false } } },
        { 2, 72, 600, 0, 2, { { 0, 1200, false }, { 2, 1200, true }, { 0, 600, false } } },
    };
    for (const rc& c : cases) {
        nr_rate_match_params p = rm_params(c.bg, c.zc, c.kp, c.n_ref, c.qm);
        const std::size_t N = p.n(), cols = N / c.zc, K = nr_ldpc_k(c.bg, c.zc);
        std::vector<float> soft(N, 0.0f), want(N, 0.0f);
        std::vector<std::uint8_t> columns(cols, 0);
        nr_ldpc_decoder told(c.bg, c.zc, 4), reads_all(c.bg, c.zc, 4);
        unsigned seed = 1;
        for (const tx& t : c.seq) {
            p.rv = t.rv;
            const auto ref = reference_positions(c.bg, c.zc, c.kp, p.n_cb(), t.rv, t.E, c.qm);
            // integer LLRs of both signs: every sum is exact in any order
            std::vector<float> llr(t.E);
            std::mt19937 rng(seed++);
            if (!t.combine)
                std::fill(want.begin(), want.end(), 0.0f);
            for (std::size_t k = 0; k < t.E; k++) {
                llr[k] = static_cast<float>(static_cast<int>(rng() % 41) - 20);
                want[ref[k]] += llr[k];
            }
            nr_rate_recover(llr.data(), p, t.E, soft.data(), t.combine, columns.data());
            for (std::size_t k = 0; k < N; k++) {
                const bool filler = k >= c.kp - 2 * c.zc && k < K - 2 * c.zc;
                ASSERT_EQ(soft[k], filler ? INFINITY : want[k])
                    << "BG" << c.bg << " rv " << t.rv << " E " << t.E << " position " << k;
            }
            for (std::size_t j = 0; j < cols; j++) {
                if (!columns[j]) {
                    for (std::size_t k = j * c.zc; k < (j + 1) * c.zc; k++)
                        ASSERT_EQ(soft[k], 0.0f) << "unflagged column " << j << " rv " << t.rv;
                }
            }
            std::vector<std::uint8_t> a(K), b(K);
            const auto ra = told.decode(soft.data(), a.data(), columns.data());
            const auto rb = reads_all.decode(soft.data(), b.data());
            EXPECT_EQ(a, b) << "BG" << c.bg << " rv " << t.rv << " E " << t.E;
            EXPECT_EQ(ra.iterations, rb.iterations);
            EXPECT_EQ(ra.parity_ok, rb.parity_ok);
        }
    }
}

TEST(NrRateMatch, CodeBlockSizesE)
{
    // G = 1000, C = 3, Qm = 4: G / Qm = 250 symbols, mod(250, 3) = 1: the first 2 blocks get
    // 4 floor(250 / 3) = 332 bits, the last 4 ceil(250 / 3) = 336 (sum 1000).
    EXPECT_EQ(nr_code_block_e(1000, 3, 4), (std::vector<std::size_t>{ 332, 332, 336 }));
    EXPECT_EQ(nr_code_block_e(1200, 3, 4), (std::vector<std::size_t>{ 400, 400, 400 }));
    EXPECT_NE(nrsar_test::error_of([] { nr_code_block_e(1001, 3, 4); }).find("G"), std::string::npos);
    nr_rate_match_params p;
    p.k_prime = 8448;
    p.rv = 4;
    EXPECT_NE(nrsar_test::error_of([&] { p.validate(); }).find("rv"), std::string::npos);
}

TEST(NrTbs, WorkedCasesOf38214)
{
    // Each worked by hand from 5.1.3.2 (N_RE = min(156, 12 N_symb - N_DMRS) n_PRB):
    // qam64 MCS 0 (Qm 2, R 120/1024), 1 PRB, 14 symbols, 12 DMRS RE: N_RE = 156,
    // N_info = 36.5625, n = 3, N'_info = max(24, 8 floor(4.57)) = 32 -> TBS 32.
    EXPECT_EQ(nr_tbs(nr_mcs_table::qam64, 0, 1, 14, 12), 32u);
    // qam64 MCS 10 (Qm 4, R 340), 10 PRB, 12 symbols, 6 DMRS RE: N_RE = 1380,
    // N_info = 1832.8125, n = 4, N'_info = 16 floor(114.55) = 1824 -> table: 1864.
    EXPECT_EQ(nr_tbs(nr_mcs_table::qam64, 10, 10, 12, 6), 1864u);
    // qam64 MCS 20 (Qm 6, R 567), 10 PRB, 14 symbols, 12 DMRS: N_RE = 1560, N_info = 5182.73,
    // n = floor(log2 5158.73) - 5 = 7, N'_info = 128 round(40.30) = 5120, R > 1/4, <= 8424:
    // TBS = 8 ceil(5144 / 8) - 24 = 5120.
    EXPECT_EQ(nr_tbs(nr_mcs_table::qam64, 20, 10, 14, 12), 5120u);
    // qam64 MCS 0, 273 PRB: N_RE = 42588, N_info = 9981.5625, n = 8, N'_info = 256 round(38.90)
    // = 9984, R <= 1/4: C = ceil(10008 / 3816) = 3, TBS = 24 ceil(10008 / 24) - 24 = 9984.
    EXPECT_EQ(nr_tbs(nr_mcs_table::qam64, 0, 273, 14, 12), 9984u);
    // qam256 MCS 27 (Qm 8, R 948), 273 PRB: N_info = 315417.375, n = 13, N'_info = 8192
    // round(38.50) = 319488, C = ceil(319512 / 8424) = 38, TBS = 304 ceil(1051.03) - 24 = 319784.
    EXPECT_EQ(nr_tbs(nr_mcs_table::qam256, 27, 273, 14, 12), 319784u);
    // qam256 MCS 20 has R = 682.5 / 1024 exactly.
    EXPECT_EQ(nr_mcs(nr_mcs_table::qam256, 20).rate_x1024, 682.5);
    EXPECT_EQ(nr_mcs(nr_mcs_table::qam256, 20).qm, 8u);
    EXPECT_NE(nrsar_test::error_of([] { nr_mcs(nr_mcs_table::qam64, 29); }).find("mcs"), std::string::npos);
    EXPECT_NE(nrsar_test::error_of([] { nr_parse_mcs_table("qam1024"); }).find("mcs_table"), std::string::npos);
}

TEST(NrTbs, ScramblingInit)
{
    // 38.211 6.3.1.1: c_init = n_RNTI 2^15 + n_ID.
    EXPECT_EQ(nr_scrambling_c_init(0x4601, 500), 0x4601u * 32768u + 500u);
    EXPECT_EQ(nr_scrambling_c_init(65535, 1023), 65535u * 32768u + 1023u);
    EXPECT_NE(nrsar_test::error_of([] { nr_scrambling_c_init(1, 1024); }).find("n_id"), std::string::npos);
}

namespace {

// BPSK-style LLRs of bits over AWGN at Es/N0 (dB); infinite SNR: +-5.
std::vector<float> channel(const std::vector<std::uint8_t>& bits, double esn0_db, unsigned seed)
{
    std::mt19937 rng(seed);
    const double sigma = std::sqrt(0.5 / std::pow(10.0, esn0_db / 10.0));
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<float> llr(bits.size());
    for (std::size_t i = 0; i < bits.size(); i++)
        llr[i] = static_cast<float>(2.0 * ((bits[i] ? -1.0 : 1.0) + noise(rng)) / (sigma * sigma));
    return llr;
}

} // namespace

TEST(NrUlsch, ChainOf38212Section62)
{
    struct uc {
        std::size_t A;
        double R;
        unsigned qm;
        std::size_t G;
    };
    const uc cases[] = {
        { 25104, 0.9, 8, 28800 },  // BG1, CRC24A, C = 3
        { 1864, 340 / 1024.0, 4, 5520 }, // BG2 (A <= 3824, R <= 0.67), CRC16, C = 1
        { 9984, 120 / 1024.0, 2, 85176 }, // BG2 at R <= 1/4 with C = 3 (38.214 used 3816)
        { 100, 0.5, 2, 240 },     // BG2, Kb = 6
    };
    const std::uint32_t c_init = nr_scrambling_c_init(0x4601, 17);
    for (const uc& u : cases) {
        nr_ulsch ul(u.A, u.R, u.qm, u.G);
        const auto a = random_bits(u.A, static_cast<unsigned>(u.A));
        std::vector<std::uint8_t> out(u.G), back(u.A);
        ul.encode(a.data(), 0, c_init, out.data());
        // Descrambled by c(i) of 38.211 5.2.1, the slot holds the rate-matched code blocks
        // in block order (6.2.6), each E_r long.
        gold_sequence c(c_init);
        std::vector<std::uint8_t> cs(u.G);
        c.generate_unpacked(cs.data(), u.G);
        const auto& s = ul.segmentation();
        std::vector<std::uint8_t> tb(s.B), cb(std::size_t{ s.C } * s.K), d(nr_ldpc_n(s.base_graph, s.Zc));
        nr_crc(u.A > 3824 ? nr_crc_type::crc24a : nr_crc_type::crc16).attach(a.data(), u.A, tb.data());
        nr_segment(tb.data(), s, cb.data());
        nr_ldpc_encoder enc(s.base_graph, s.Zc);
        nr_rate_match_params p;
        p.base_graph = s.base_graph;
        p.zc = s.Zc;
        p.k_prime = s.K_prime;
        p.qm = u.qm;
        std::size_t pos = 0, mismatches = 0;
        for (unsigned r = 0; r < s.C; r++) {
            enc.encode(cb.data() + std::size_t{ r } * s.K, d.data());
            std::vector<std::uint8_t> f(ul.e()[r]);
            nr_rate_match(d.data(), p, f.size(), f.data());
            for (std::size_t k = 0; k < f.size(); k++)
                mismatches += (out[pos + k] ^ cs[pos + k]) != f[k];
            pos += f.size();
        }
        EXPECT_EQ(pos, u.G);
        EXPECT_EQ(mismatches, 0u) << "A " << u.A;
        // Noiseless round trip; a wrong c_init breaks the TB CRC.
        const auto llr = channel(out, INFINITY, 1);
        const auto res = ul.decode(llr.data(), 0, c_init, false, back.data());
        EXPECT_TRUE(res.tb_crc_ok && res.parity_ok) << "A " << u.A;
        EXPECT_EQ(res.cb_crc_ok, s.C);
        EXPECT_EQ(back, a);
        EXPECT_FALSE(ul.decode(llr.data(), 0, c_init + 1, false, back.data()).tb_crc_ok);
    }
}

TEST(NrUlsch, NanLlrsAreErasuresNextToInfiniteOnes)
{
    // Noiseless slot (LLRs +-5, every 7th +-inf: a known bit) with 2 % of them NaN (erasures, decoded as
    // 0) in the vector body and the scalar tail of the descrambler (G = 28802 = 4 k + 2): the
    // TB decodes. A NaN that reached the decoder, or an inf that did not saturate, would not.
    nr_ulsch ul(25104, 0.9, 2, 28802);
    const auto a = random_bits(25104, 7);
    std::vector<std::uint8_t> out(28802), back(25104);
    ul.encode(a.data(), 0, 99, out.data());
    auto llr = channel(out, INFINITY, 1); // +-5
    for (std::size_t k = 0; k < llr.size(); k += 7)
        llr[k] = std::copysign(INFINITY, llr[k]);
    for (std::size_t k = 3; k < llr.size(); k += 50)
        llr[k] = NAN;
    llr[llr.size() - 1] = NAN;
    const auto res = ul.decode(llr.data(), 0, 99, false, back.data());
    EXPECT_TRUE(res.tb_crc_ok && res.parity_ok);
    EXPECT_EQ(back, a);
}

TEST(NrUlsch, HarqCombiningRecoversWhatOneTransmissionCannot)
{
    // A = 25104 at R = 0.9 into G = 28800 (effective rate 0.873, QPSK bits as BPSK LLRs).
    // Es/N0 = 1 dB is about 1.6 dB below the BI-AWGN limit of that rate: rv 0 alone cannot
    // decode; rv 0 + rv 2 (two transmissions: rate ~0.44, limit ~ -2.5 dB) decodes.
    nr_ulsch ul(25104, 0.9, 2, 28800);
    const auto a = random_bits(25104, 5);
    std::vector<std::uint8_t> tx0(28800), tx2(28800), back(25104);
    ul.encode(a.data(), 0, 1234, tx0.data());
    ul.encode(a.data(), 2, 1234, tx2.data());
    const auto l0 = channel(tx0, 1.0, 2), l2 = channel(tx2, 1.0, 3);
    EXPECT_FALSE(ul.decode(l0.data(), 0, 1234, false, back.data()).tb_crc_ok);
    const auto res = ul.decode(l2.data(), 2, 1234, true, back.data());
    EXPECT_TRUE(res.tb_crc_ok);
    EXPECT_EQ(back, a);
}
