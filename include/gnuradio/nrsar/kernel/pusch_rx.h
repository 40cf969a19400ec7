/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_KERNEL_PUSCH_RX_H
#define INCLUDED_NRSAR_KERNEL_PUSCH_RX_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/kernel/constellation.h>
#include <gnuradio/nrsar/kernel/soft_demapper.h>
#include <gnuradio/nrsar/kernel/transport_block.h>
#include <gnuradio/nrsar/params.h>
#include <gnuradio/nrsar/pusch_config.h>
#include <volk/volk_alloc.hh>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {
namespace kernel {

//! What the receiver found in one slot.
struct NRSAR_API pusch_slot_result {
    tb_result tb;           //!< the decoding of this slot (empty when the TB decoded before)
    std::uint64_t tb_index = 0;  //!< slot / repetitions: which TB the slot carries
    unsigned transmissions = 0;  //!< transmissions of the TB combined in tb (0: not decoded)
    //! True when the TB is settled with this slot: it decoded now, or this was its last
    //! transmission. The receiver reports the TB then.
    bool tb_final = false;
    double noise_var = 0.0; //!< sigma^2 per RE, from the empty odd DMRS subcarriers
    double snr_db = 0.0;    //!< mean |h|^2 over the data REs / sigma^2
    double evm_db = 0.0;    //!< mean |x - nearest point|^2 of the equalised data REs
};

/*!
 * \brief PUSCH slot receiver on the frequency-domain grid (one slot = symbols_per_slot
 * vectors of N): channel estimation on the DMRS, zero-forcing equalisation, max-log soft
 * demapping and transport block decoding.
 *
 * Per DMRS symbol l_d: LS estimate h(2i) = Y(2i, l_d) conj(r(i)) (|r| = 1), smoothed by a
 * straight-line least-squares fit over freq_window neighbouring DMRS REs (centred: the moving
 * average; shifted inside the band at the edges), linear interpolation to the odd
 * subcarriers (extrapolation for the last one). In time: linear interpolation between the DMRS symbols and linear
 * extrapolation outside them (tracks a residual CFO / common phase drift); one DMRS symbol
 * = constant. Noise: sigma^2 = mean |Y|^2 over the odd subcarriers of the DMRS symbols, which
 * the transmitter leaves empty. Equalisation x = y / h, per-RE noise variance sigma^2 / |h|^2
 * into kernel::soft_demapper, then transport_block_codec::decode, combining the
 * repetitions of a TB (pusch_config::repetitions, rv sequence of 38.214 Table 6.1.2.1-2)
 * until it decodes.
 */
class NRSAR_API pusch_rx
{
public:
    /*!
     * cfg as the transmitter's (dmrs must have at least one symbol; N >= 6); its
     * freq_window and max_iterations are the receiver's.
     */
    explicit pusch_rx(const pusch_config& cfg);
    pusch_rx(pusch_rx&&) = default;
    pusch_rx& operator=(pusch_rx&&) = default;
    pusch_rx(const pusch_rx&) = delete;
    pusch_rx& operator=(const pusch_rx&) = delete;

    const transport_block_codec& codec() const { return d_codec; }
    //! Data REs per slot (equalised symbols process() writes).
    std::size_t data_res() const { return d_data_res; }

    /*!
     * Processes one slot: grid holds symbols_per_slot * N values (symbol-major), slot is the
     * absolute slot index (DMRS use slot % slots_per_frame, the TB slot / repetitions). When eq
     * is not null it receives data_res() equalised data symbols (subcarrier order, symbol by
     * symbol).
     */
    pusch_slot_result process(const gr_complex* grid, std::uint64_t slot, gr_complex* eq = nullptr);

    //! Threads of process(): 1 or 2 (the code blocks are decoded on two; same results).
    void set_threads(unsigned threads);
    unsigned threads() const { return d_threads; }

    //! Use the equaliser's AVX2 path when the CPU has it (default); false forces the generic
    //! path. Both give the same floats.
    void set_simd(bool allow);
    bool simd() const { return d_simd; }

private:
    double equalise(const gr_complex* y, float s2, unsigned n, gr_complex* x, float* nv);

    numerology d_num;
    dmrs_config d_dmrs;
    soft_demapper d_demapper;
    transport_block_codec d_codec;
    unsigned d_threads = 1;
    unsigned d_window;
    std::size_t d_data_res;
    std::vector<unsigned> d_data_symbols;
    pusch_config d_cfg;
    bool d_simd;                       // equaliser's AVX2 path (runtime check)
    bool d_done = false;               // the current TB decoded at an earlier repetition
    unsigned d_transmissions = 0;      // of the current TB, combined so far
    std::uint64_t d_last_slot = ~std::uint64_t{ 0 };
    // per slot in frame, per DMRS symbol: DMRS values on subcarriers 0, 2, ...
    std::vector<std::vector<gr_complex>> d_dmrs_values;
    std::vector<std::vector<gr_complex>> d_h_dmrs; // channel per DMRS symbol, all N subcarriers
    std::vector<gr_complex> d_ls;
    std::vector<std::complex<double>> d_s0, d_s1; // prefix sums of ls(j), j ls(j)
    volk::vector<gr_complex> d_h;   // channel of one data symbol
    volk::vector<float> d_g;        // |h|^2 of one data symbol
    volk::vector<gr_complex> d_x;   // equalised data REs of the slot
    volk::vector<float> d_nv;       // per-RE noise variance after equalisation
    volk::vector<float> d_llr;
};

} // namespace kernel
} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_KERNEL_PUSCH_RX_H */
