/* -*- c++ -*- */
/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

#ifndef INCLUDED_NRSAR_PARAMS_H
#define INCLUDED_NRSAR_PARAMS_H

#include <gnuradio/nrsar/api.h>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace nrsar {

//! Constellations (3GPP TS 38.211 section 5.1 Gray mapping for QPSK/QAM, E{|s|^2} = 1).
enum class modulation { QPSK, QAM16, QAM64, QAM256, PSK8, PSK16 };

//! What the transmit grid carries (SPEC section 2, paper section V-C).
enum class tx_mode {
    DATA,    //!< every RE carries data (data-aided imaging)
    SRS,     //!< SRS pilot only: comb, one symbol per SRS slot, other REs empty
    DATA_SRS //!< data everywhere except the SRS REs, which carry the pilot
};

//! Per-RE filter of SPEC section 4, eq. (25).
enum class filter_type { RF, MF, WF };

//! Speed of light in vacuum [m/s].
constexpr double speed_of_light = 299792458.0;

/*!
 * \brief OFDM numerology shared by every block (SPEC section 2).
 *
 * The transmit grid has num_subcarriers rows (one per resource element of a symbol)
 * and one column per OFDM symbol. fft_size and cp_samples describe the time-domain
 * waveform an SDR would carry: sample rate fft_size * subcarrier_spacing_hz, cyclic
 * prefix cp_samples samples long.
 */
struct NRSAR_API numerology {
    double subcarrier_spacing_hz = 30e3; //!< Delta f [Hz]
    unsigned num_subcarriers = 3333;     //!< N, subcarriers carrying resource elements
    unsigned fft_size = 4096;            //!< time-domain FFT size (>= N)
    unsigned cp_samples = 1024;          //!< cyclic prefix length in samples
    unsigned symbols_per_slot = 14;      //!< OFDM symbols per NR slot
    unsigned slots_per_frame = 20;       //!< slots per 10 ms frame (30 kHz: 20)

    double sample_rate_hz() const { return fft_size * subcarrier_spacing_hz; }
    double useful_symbol_s() const { return 1.0 / subcarrier_spacing_hz; }    //!< Tp
    double cp_s() const { return cp_samples / sample_rate_hz(); }             //!< Tcp
    double symbol_s() const { return useful_symbol_s() + cp_s(); }            //!< Tsym
    double prf_hz() const { return 1.0 / symbol_s(); }                        //!< 1/Tsym
    double bandwidth_hz() const { return num_subcarriers * subcarrier_spacing_hz; } //!< Br
    /*!
     * Subcarrier k0 that the time-domain waveform puts at DC: floor(N / 2) rounded down to an
     * even number, so subcarrier n sits at baseband frequency (n - k0) Delta f (FFT bin
     * (n - k0) mod fft_size) and even subcarriers land on even bins. The TF model's frequency
     * fc + n Delta f (SPEC section 3) then means an RF carrier at fc + k0 Delta f.
     */
    unsigned dc_subcarrier() const { return (num_subcarriers / 2) & ~1u; }
    //! Slant-range spacing of bin k of an nfft-point range IFFT: c / (2 nfft Delta f).
    double range_bin_m(unsigned nfft) const;
    //! Unambiguous slant range of the subcarrier grid, c / (2 Delta f).
    double max_unambiguous_range_m() const;

    //! Throws std::invalid_argument naming the field, its value and the limit.
    void validate() const;

    /*!
     * Presets: "paper" (3333 x 30 kHz, 4096 FFT, Tcp 8.33 us), "small" (512 subcarriers,
     * otherwise paper), "tiny" (64 subcarriers, for tests), "nr273" (273 RB = 3276
     * subcarriers, 4096 FFT, normal CP of 288 samples = 2.34 us), "sdr20" (51 RB = 612
     * subcarriers, 1024 FFT at 30.72 Msps, Tcp 8.33 us).
     */
    static numerology preset(const std::string& name);
    static std::vector<std::string> preset_names();
};

/*!
 * \brief SRS pilot layout (SPEC section 2): a comb over num_rb resource blocks
 * starting at start_subcarrier, one SRS symbol per SRS slot.
 */
struct NRSAR_API srs_config {
    unsigned start_subcarrier = 1667; //!< first subcarrier of the SRS band
    unsigned num_rb = 24;             //!< resource blocks (12 subcarriers each)
    unsigned comb = 4;                //!< every comb-th subcarrier carries SRS
    unsigned comb_offset = 0;         //!< which subcarrier of the comb (< comb)
    unsigned period_slots = 2;        //!< one SRS slot every period_slots slots
    unsigned symbol_in_slot = 13;     //!< OFDM symbol of the slot that carries SRS

    unsigned num_subcarriers() const { return num_rb * 12; }
    //! Throws std::invalid_argument when the band does not fit the grid of num.
    void validate(const numerology& num) const;
};

/*!
 * \brief PUSCH DMRS layout of the uplink slot (3GPP TS 38.211 6.4.1.1, configuration type 1,
 * single port, two CDM groups without data).
 *
 * The OFDM symbols of every slot listed in symbols (positions 0 .. symbols_per_slot - 1,
 * strictly increasing) carry the DMRS on the even subcarriers (n % 2 == 0) of the whole grid:
 * QPSK values of the Gold sequence c(n) (SPEC section 2) with
 * c_init = (2^17 (14 slot + symbol + 1) (2 scrambling_id + 1) + 2 scrambling_id) mod 2^31
 * (slot = slot index within the frame). The odd subcarriers of those symbols are left empty,
 * so a DMRS symbol repeats with period fft_size / 2 in time (what the base station's
 * timing and CFO acquisition looks for). An empty symbols list means no DMRS (every RE of the
 * grid carries data, the radar-only default). The imaging side uses every RE, DMRS included.
 */
struct NRSAR_API dmrs_config {
    std::vector<unsigned> symbols;  //!< DMRS symbol positions in the slot (NR: {2, 11})
    unsigned scrambling_id = 0;     //!< N_ID^{n_SCID}, 0 .. 65535

    bool enabled() const { return !symbols.empty(); }
    //! True when symbol l of a slot carries DMRS.
    bool is_dmrs_symbol(unsigned symbol_in_slot) const;
    void validate(const numerology& num) const;

    //! Presets: "none" (no DMRS), "pusch2" ({2, 11}: NR's 1+1 additional position),
    //! "pusch1" ({2}), "pusch4" ({2, 5, 8, 11}).
    static dmrs_config preset(const std::string& name);
    static std::vector<std::string> preset_names();
};

/*!
 * \brief Platform geometry: carrier, straight track along y at height H (SPEC section 2).
 *
 * The platform is at (0, track_start_m + v t, H) at slow time t; one aperture lasts
 * aperture_s seconds.
 */
struct NRSAR_API geometry {
    double carrier_hz = 3.5e9;   //!< fc [Hz]
    double velocity_mps = 50.0;  //!< v [m/s]
    double height_m = 1000.0;    //!< H [m]
    double track_start_m = 0.0;  //!< platform y at t = 0 [m]
    double aperture_s = 2.0;     //!< Ta [s]

    double wavelength_m() const { return speed_of_light / carrier_hz; }
    //! Symbols in one aperture, M = round(Ta / Tsym).
    std::uint64_t symbols_per_aperture(const numerology& num) const;
    //! Normalised Doppler eta = 2 v fc / (c Delta f) (SPEC section 2, footnote 3).
    double normalised_doppler(const numerology& num) const;

    void validate() const;

    //! Presets: "paper" (3.5 GHz, 50 m/s, 1000 m, 2 s), "short" (paper, 0.1 s aperture).
    static geometry preset(const std::string& name);
    static std::vector<std::string> preset_names();
};

//! A point scatterer on the ground (z = 0); rcs is the scattered power |alpha|^2.
struct NRSAR_API point_target {
    double x_m = 0.0;  //!< ground range offset from the track [m]
    double y_m = 0.0;  //!< along-track position [m]
    double rcs = 1.0;  //!< power (linear), amplitude sqrt(rcs)
    double phase_rad = 0.0; //!< phase of the reflection coefficient

    point_target() = default;
    point_target(double x, double y, double r = 1.0, double phase = 0.0)
        : x_m(x), y_m(y), rcs(r), phase_rad(phase)
    {
    }
    //! Exact slant range, eq. (8), from the platform at along-track position y_p.
    double slant_range_m(const geometry& geo, double platform_y_m) const;

    /*!
     * Parses one target "X,Y[,RCS[,PHASE_DEG]]": ground range X and along-track Y [m], RCS
     * linear power (default 1), reflection phase in degrees (default 0). Each field is a
     * decimal number as Python's float() reads it (surrounding whitespace, a sign, exponent,
     * '_' between digits, inf, nan). Throws std::invalid_argument naming the target index,
     * the field and the text; does not validate the values (scene::validate does).
     */
    static point_target parse(const std::string& text, std::size_t index = 0);
};

//! A scene: point targets; the first one is the reference target of the metrics.
struct NRSAR_API scene {
    std::vector<point_target> targets;

    double total_rcs() const;
    void validate() const;

    /*!
     * Parses a scene preset name ("paper3") or a target list
     * "X,Y[,RCS[,PHASE_DEG]];X,Y...": targets separated by ';' (empty items skipped), each as
     * point_target::parse reads it. The one grammar of GRC, the apps and scripts
     * (Python make_scene). Throws std::invalid_argument naming the target index, the field
     * and the text; an empty text gives an empty scene. Does not validate.
     */
    static scene parse(const std::string& text);

    //! Presets: "paper3" (T1 (300,100), T2 (250,100), T3 (300,140), unit RCS),
    //! "single" (T1 only).
    static scene preset(const std::string& name);
    static std::vector<std::string> preset_names();
};

/*!
 * \brief What a scene needs of the numerology and geometry (SPEC section 2).
 */
struct NRSAR_API scene_extent {
    double min_slant_range_m = 0.0;
    double max_slant_range_m = 0.0; //!< over the whole aperture (exact range)
    double min_doppler_hz = 0.0;    //!< echo Doppler band over the aperture
    double max_doppler_hz = 0.0;
    double doppler_bandwidth_hz() const { return max_doppler_hz - min_doppler_hz; }
};

NRSAR_API scene_extent compute_extent(const geometry& geo, const scene& scn);

/*!
 * \brief Checks that numerology, geometry and scene fit together.
 *
 * Throws std::invalid_argument when the geometry breaks the TF echo model: the
 * farthest round trip 2 R_max / c longer than the cyclic prefix, eta >= 0.1, a
 * target beyond the unambiguous range. Returns warnings (with the numbers) for
 * conditions that degrade the image but are legitimate experiments, such as a
 * pulse rate below the scene's Doppler band (azimuth aliasing). symbols_per_pulse is
 * the slow-time sampling interval in OFDM symbols: 1 for data-aided imaging,
 * 14 * period_slots for one SRS symbol per SRS slot. (With eta < 0.1 the full PRF always
 * exceeds the Doppler band, since 2 v / lambda = eta Delta f.)
 */
NRSAR_API std::vector<std::string> check_scenario(const numerology& num,
                                                  const geometry& geo,
                                                  const scene& scn,
                                                  unsigned symbols_per_pulse = 1);

} // namespace nrsar
} // namespace gr

#endif /* INCLUDED_NRSAR_PARAMS_H */
