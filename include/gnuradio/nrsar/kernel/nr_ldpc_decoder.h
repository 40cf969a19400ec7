/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_NR_LDPC_DECODER_H
#define INCLUDED_NRSAR_KERNEL_NR_LDPC_DECODER_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/nr_ldpc.h>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! What one decode() did.
struct nr_ldpc_decode_result {
    unsigned iterations = 0; //!< full iterations run (1 .. max_iterations)
    bool parity_ok = false;  //!< H x = 0 on the received rows when it stopped
    //! The int8 decode ended near a codeword and the word was decoded again in int16 (the
    //! bits, iterations and parity_ok are that decode's).
    bool redecoded = false;
};

/*!
 * \brief Layered offset min-sum LDPC decoder for the codes of TS 38.212 5.3.2, int8 or int16
 * fixed point.
 *
 * Each base-graph row is a layer; a layer reads the a-posteriori LLRs of its columns,
 * cyclically shifted by P_ij, updates its check-to-variable messages
 *   R_e = prod_{e' != e} sign(T_e') max(min_{e' != e} |T_e'| - beta, 0),   T_e = L_e - R_e(old)
 * and writes L_e = T_e + R_e back, so later layers of the same iteration see the update.
 * beta = offset_llr = 0.5 in the units of the input LLRs (natural-log likelihood ratios, as
 * a demapper given the noise variance writes them): against AFF3CT's published 5G NR curves
 * it is 0.4-0.5 dB better than the normalised min-sum (factor 0.75) this decoder had at 10
 * iterations (docs/nr_coding.md, "Against published curves").
 * Only rows whose parity column (the degree-one extension columns of 38.212) carries any
 * LLR are decoded: the others cannot pass information. Stops early when the hard decisions
 * satisfy every decoded row: each row's sign test right after its update, the rows that
 * failed it tested again at the end of the iteration, then a full syndrome on the final
 * hard decisions.
 *
 * Fixed point: a word whose decoded rows give some column at most int8_max_degree (5) edges
 * (high rates: BG1 at rate 0.9 decodes 5 rows, d_max 5) is decoded in int8, every value
 * saturating at +-127; the float input is scaled so that (mean sqrt|L|)^2 maps to
 * clamp(168 / (1 + d_max), 8, 32), d_max the largest column degree of the decoded rows, but
 * by at least 1 / offset_llr (beta one step: the large LLRs of 64- and 256-QAM rounded it to
 * 0), and clamped to +-63. Other words are decoded in int16 at 4x that scale, input clamped to
 * +-252, values saturating at +-32767: in int8 their a-posteriori sums saturated and left an
 * error floor (BG2 K' 512 at rate 1/2: FER 5e-3 at 2.5 dB, now 1e-4 as AFF3CT's float
 * offset min-sum; docs/nr_coding.md). An int8 word that fails with at most 1 / 32 of its
 * decoded checks unsatisfied (where saturation and the offset's coarse int8 step leave a
 * word; one below the code's threshold leaves many more) is decoded again in int16, and so
 * is one that fails further from a codeword although the mean mutual information of its
 * LLRs, 1 - h2(1 / (1 + e^|L|)) per received value, exceeds the code rate by
 * capacity_margin (0.04): the cost falls on such words only, never on words the channel
 * could not carry (BG1 at rate 0.9: the int8 loss of 0.1 dB in the waterfall and the int8
 * floor of about 2.5e-4 from Eb/N0 4.45 dB are gone; failures as in int16 everywhere).
 * +infinity marks known bits (fillers) and becomes the largest value.
 * The AVX2 path (32 int8 or 16 int16 lanes per instruction, runtime CPU check) and the scalar path
 * compute the same integers.
 */
class NRSAR_API nr_ldpc_decoder
{
public:
    /*!
     * \param base_graph      1 or 2
     * \param zc              a lifting size of Table 5.3.2-1
     * \param max_iterations  >= 1
     */
    nr_ldpc_decoder(int base_graph, unsigned zc, unsigned max_iterations = 8);

    int base_graph() const { return d_bg; }
    unsigned zc() const { return d_zc; }
    std::size_t n() const { return nr_ldpc_n(d_bg, d_zc); }
    std::size_t k() const { return nr_ldpc_k(d_bg, d_zc); }
    unsigned max_iterations() const { return d_max_iter; }
    void set_max_iterations(unsigned max_iterations);

    /*!
     * \brief Decodes N LLRs of d_0 .. d_{N-1} (positive = bit 0; 0 = not received;
     * +inf = known 0, e.g. fillers; NaN counts as 0) into the K bits c_0 .. c_{K-1}.
     * nonzero_columns (optional, N / Zc flags): the columns of Zc LLRs flagged 0 hold only
     * zeros and are not read (nr_rate_recover's record); the same result as without.
     */
    nr_ldpc_decode_result
    decode(const float* llr, std::uint8_t* c, const std::uint8_t* nonzero_columns = nullptr);

    //! The same from int8 LLRs (clamped to +-127), e.g. from a fixed-point demapper, not
    //! rescaled (in int16 the sums do not saturate); offset: beta in their units (negative
    //! counts as 0).
    nr_ldpc_decode_result decode_int8(const std::int8_t* llr, std::uint8_t* c, std::int8_t offset = 1);

    //! beta of the check-node update, in LLR units of decode()'s input.
    static constexpr double offset_llr = 0.5;

    //! Use the AVX2 path when the CPU has it (default); false forces the scalar path.
    void set_simd(bool allow);
    bool simd() const { return d_simd; }

private:
    struct layer {
        unsigned row;
        unsigned first_edge; // into d_edges and d_r
        unsigned degree;
    };
    // T = std::int8_t or std::int16_t: the message width of this word
    template <typename T>
    nr_ldpc_decode_result quantize_and_run(const float* llr, float scale, std::uint8_t* c);
    template <typename T>
    nr_ldpc_decode_result widen_and_run(const std::int8_t* llr, std::uint8_t* c);
    template <typename T>
    nr_ldpc_decode_result run(std::uint8_t* c); // decodes d_l over d_active
    //! d_active = the rows to decode given which columns received LLRs (d_received);
    //! returns the largest column degree over them.
    unsigned select_layers();
    template <typename T>
    void gather(const layer& ly); // the row's columns, shifted by P_ij, into d_t
    template <typename T>
    unsigned unsatisfied(const layer& ly); // unsatisfied checks of one row, current decisions
    void set_offset(float scale);          // d_offset = beta at this input scale
    //! True when the int8 decode res failed with at most 1 / near_codeword_fraction of the
    //! decoded checks unsatisfied: then the word is decoded again in int16.
    bool near_codeword(const nr_ldpc_decode_result& res);
    //! True when the int8 decode res failed although the mean mutual information of the
    //! received LLRs exceeds the code rate by capacity_margin: then the word is decoded again
    //! in int16 too.
    bool above_capacity(const float* llr, const nr_ldpc_decode_result& res) const;
    static nr_ldpc_decode_result redecoded(nr_ldpc_decode_result res);
    using sums_fn = void (*)(const float*, std::size_t, float*, float*);
    //! fn over the received columns of llr in 8 lane sums; returns n8 (the values from n8 to
    //! n are the caller's).
    std::size_t received_sums(const float* llr, sums_fn fn, float* part, float* cnt) const;

    //! Words whose decoded rows give a column more edges than this decode in int16: in int8
    //! their a-posteriori sums saturate (the error floor of low-rate words).
    static constexpr unsigned int8_max_degree = 5;
    //! BG1 Zc 384 rate 0.9 at Eb/N0 3.8-4.3 dB: the words int16 decodes after int8 failed
    //! had 1 .. 98 of the 1920 checks unsatisfied (99 % at most 60), the others up to 400.
    static constexpr unsigned near_codeword_fraction = 32;
    //! Bits of mutual information per received value above the rate from which a failed
    //! int8 word is decoded again. BG1 Zc 384 rate 0.9 on BPSK: 0.04 is Eb/N0 4.15 dB, the
    //! BLER 1-2 % point at 8 iterations; the int8 floor words had 0.046-0.055, words at the
    //! BLER 10 % point 0.037 (one word's estimate scatters by about 0.0017).
    static constexpr double capacity_margin = 0.04;

    int d_bg;
    unsigned d_zc;
    unsigned d_zp; // Zc rounded up to the SIMD width
    unsigned d_cols;
    unsigned d_max_iter;
    bool d_simd;
    int d_offset = 0;                     // beta in fixed-point units for the current word
    std::vector<nr_lifted_edge> d_edges; // all rows, row by row
    std::vector<layer> d_layers;          // every row of H
    std::vector<unsigned> d_row_parity;   // the degree-one column of each row (or none)
    std::vector<std::uint8_t> d_received; // per column: received a non-zero LLR
    // Sized for int16; an int8 word uses the first half of each (both views of one store).
    std::vector<std::int16_t> d_l;        // a-posteriori LLRs, cols x zp
    std::vector<std::int16_t> d_r;        // check-to-variable messages, edges x zp
    std::vector<std::int16_t> d_t;        // the gathered columns of one layer, degree x zp
    std::vector<layer> d_active;          // the layers decoded for this word
    std::vector<const layer*> d_failed;   // layers whose check failed at their visit
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_NR_LDPC_DECODER_H */
