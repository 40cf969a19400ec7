/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PUSCH_CONFIG_H
#define INCLUDED_NRSAR_PUSCH_CONFIG_H

#include <gnuradio/nrsar/api.h>
#include <gnuradio/nrsar/params.h>
#include <cstdint>
#include <string>

namespace gr {
namespace nrsar {

//! Channel coding of the PUSCH data bits.
enum class pusch_coding {
    NONE,   //!< CRC24A only, hard decisions (no LDPC)
    NR_LDPC //!< the UL-SCH of TS 38.212 6.2 (TBS of 38.214 5.1.3.2)
};

//! c_init of the data scrambling (TS 38.211 6.3.1.1).
enum class pusch_scrambling {
    STANDARD, //!< c_init = n_RNTI 2^15 + n_ID, the same every slot (38.211)
    //! Non-standard: c_init = ((2^15 n_ID + (slot mod 2^15)) 0x9E3779B1 + 0x2545F491) mod 2^31,
    //! a fresh sequence every slot, so a low-entropy payload gives no slot-periodic radar
    //! reference (docs/nr_coding.md, "Scrambling and the radar").
    PER_SLOT
};

/*!
 * \brief The PUSCH of the UAV backhaul as pusch_encoder and pusch_receiver share it: grid,
 * modulation, DMRS, channel coding (MCS, rv, repetitions), scrambling, receiver settings.
 * One layer, transform precoding off.
 *
 * With coding NR_LDPC the modulation is the MCS's (mod must equal its Qm) and the TBS is
 * 38.214 5.1.3.2 on the grid the radar uses: n_PRB = floor(N / 12), 14 symbols,
 * N_DMRS^PRB = 12 per DMRS symbol (the odd subcarriers of a DMRS symbol carry no data),
 * G = every data RE of the N subcarriers times Qm.
 */
struct NRSAR_API pusch_config {
    numerology num;
    modulation mod = modulation::QAM256;
    dmrs_config dmrs = dmrs_config::preset("pusch2");
    pusch_coding coding = pusch_coding::NR_LDPC;
    std::string mcs_table = "qam256"; //!< "qam64" (38.214 Table 5.1.3.1-1) or "qam256" (-2)
    unsigned mcs = 27;                //!< row of the table (qam256: 27 = 256QAM, R 948/1024)
    unsigned rv = 0;                  //!< rv_id of the first transmission, 0 .. 3
    //! pusch-AggregationFactor (38.214 6.1.2.1): each TB is sent in 1, 2, 4 or 8 consecutive
    //! slots with the rv sequence 0, 2, 3, 1 of Table 6.1.2.1-2 (starting at rv); the
    //! receiver combines them (HARQ soft combining) until the TB CRC holds.
    unsigned repetitions = 1;
    unsigned n_rnti = 0x4601; //!< C-RNTI, 0 .. 65535
    unsigned n_id = 0;        //!< dataScramblingIdentityPUSCH, 0 .. 1023
    pusch_scrambling scrambling = pusch_scrambling::STANDARD;
    unsigned freq_window = 3;      //!< receiver: DMRS REs per channel estimate (odd >= 1)
    unsigned max_iterations = 8;   //!< receiver: LDPC iterations (>= 1)
    std::uint64_t max_queued_bytes = 1u << 20; //!< encoder: bound of the PDU queue (>= 1)
    //! encoder: absolute index of its first slot (scrambling, rv position; the first slot
    //! starts a TB even inside a TB's repetitions), so that with the PDUs from that slot's TB
    //! on it continues the stream of an encoder from slot 0 (nrsar-process's strip tasks)
    std::uint64_t first_slot = 0;

    //! Throws std::invalid_argument naming the field, its value and the limit.
    void validate() const;
    //! rv of the transmission in slot position pos (0 .. repetitions - 1) of a TB.
    unsigned rv_of(unsigned pos) const;
};

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PUSCH_CONFIG_H */
