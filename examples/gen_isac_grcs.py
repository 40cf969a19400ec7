#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Writes the ISAC example flowgraphs (examples/isac_*.grc) from shared pieces, so the Qt
graph, its headless twin, the USRP / Soapy front ends and the loopback keep the same blocks
and parameters. Edit here and rerun (or edit a .grc in GRC and keep this script in step).

usage: gen_isac_grcs.py [OUTPUT_DIR]   (default: the directory of this script)"""
import os
import sys

import yaml

from grc_layout import layout, wrap

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))


class Str(str):
    pass


def _str_rep(dumper, data):
    return dumper.represent_scalar("tag:yaml.org,2002:str", data, style="'")


yaml.add_representer(Str, _str_rep)


def q(v):
    return Str(str(v))


class Graph:
    def __init__(self, gid, title, description, gui):
        self.gid, self.title, self.description, self.gui = gid, title, description, gui
        self.blocks, self.conns = [], []
        self.x, self.y = 8, 8

    def add(self, bname, bid, coord, comment="", **params):
        name = bname
        p = {k.rstrip("_"): q(v) for k, v in params.items()}
        p["comment"] = q(wrap(comment))
        self.blocks.append({"name": name, "id": bid, "parameters": p,
                            "states": {"coordinate": list(coord), "rotation": 0,
                                       "state": "enabled"}})

    def var(self, name, value, coord, comment=""):
        self.add(name, "variable", coord, comment, value=value)

    def param(self, name, label, value, coord, type_="eng_float", comment="", short=""):
        self.add(name, "parameter", coord, comment, alias="", hide="none", label=label,
                 short_id=short, type=type_, value=value)

    def c(self, a, ap, b, bp):
        self.conns.append([a, q(ap), b, q(bp)])

    def dump(self):
        doc = {
            "options": {"parameters": {
                "author": q("gr-nrsar authors"), "catch_exceptions": q("True"),
                "category": q("[NR SAR]"), "copyright": q("2026 gr-nrsar authors"),
                "description": q(self.description), "gen_cmake": q("On"),
                "gen_linking": q("dynamic"),
                "generate_options": q("qt_gui" if self.gui else "no_gui"),
                "hier_block_src_path": q(".:"), "id": q(self.gid), "max_nouts": q("0"),
                "output_language": q("python"), "placement": q("(0,0)"),
                "qt_qss_theme": q(""), "realtime_scheduling": q(""), "run": q("True"),
                "run_command": q("{python} -u {filename}"), "run_options": q("run"),
                "sizing_mode": q("fixed"), "thread_safe_setters": q(""),
                "title": q(self.title), "window_size": q("(1200,1000)")},
                "states": {"bus_sink": False, "bus_source": False, "bus_structure": None,
                           "coordinate": [8, 8], "rotation": 0, "state": "enabled"}},
            "blocks": self.blocks,
            "connections": self.conns,
            "metadata": {"file_format": 1, "grc_version": q("3.10.5.1")},
        }
        layout([doc["options"]] + self.blocks)
        with open(f"{OUT}/{self.gid}.grc", "w") as f:
            yaml.dump(doc, f, sort_keys=False, width=100, default_flow_style=None)


N = "num_subcarriers"
NUM = "sdr20"
SCENE = "'''300,2'''"
QAM = "qam16"
# the PUSCH's coding, as pusch_encoder and pusch_receiver must share it (qam256 table MCS 10 =
# 16-QAM, R 658/1024)
PUSCH = dict(coding="nr_ldpc", mcs_table="qam256", mcs="10", rv="0", repetitions="1",
             n_rnti="17921", n_id="0", scrambling="standard")


def common_vars(g, y=12):
    g.var(N, "612", (200, y), "N of the sdr20 numerology (30.72 Msps, 1024 FFT, CP 256)")
    g.var("samp_rate", "nrsar.make_numerology('sdr20').sample_rate_hz()", (200, y + 80))
    # (decim as a dict entry: GRC's setters rewrite every name of a variable, keywords too)
    g.var("chain_layout", "nrsar.chain.layout(nrsar.SimOptions(preset='sdr20', "
          f"geometry='short', scene='300,2', modulation='{QAM}', presum='cheby', "
          "**{'decim': decim}))",
          (360, y), "the imaging chain's axes: the scene's swath +- 30 m (nrsar-sim's crop)")
    g.var("range_bins", "chain_layout.image_bins", (360, y + 80))
    g.var("decim", "10", (560, y), "azimuth presum factor D (PRF 24 kHz -> 2.4 kHz)")
    g.var("aperture_symbols", "int(nrsar.make_geometry('short').symbols_per_aperture("
          "nrsar.make_numerology('sdr20')))", (560, y + 80),
          "symbols of one aperture of the short geometry (0.1 s = 2400)")
    g.add("imports", "import", (760, y), "",
          imports="from gnuradio import nrsar\nfrom gnuradio.fft import window\nimport pmt")


def payload_queue(g, coord, strobe=False):
    """The payload file queued into pusch_encoder before the graph starts, as PDUs of one
    TB's capacity (isac_chain.graph_payload, the queueing of nrsar-isac's build_transmitter):
    every slot's TB is then a function of the file alone, which the recording names.
    strobe: payload 'strobe' connects the live message strobe instead (not recorded)."""
    code = ("from gnuradio.nrsar import isac_chain\n"
            "self.payload_path = isac_chain.graph_payload(self.encoder, self.payload, "
            "self.max_queued_bytes)\n")
    if strobe:
        payload_strobe(g, "payload 'strobe': a 1000-byte PDU every 50 ms (the payload snippet "
                          "connects it); not recorded, so nrsar-process refuses the recording")
        code += ("if self.payload_path is None:\n"
                 "    self.msg_connect((self.payload_strobe, 'strobe'), (self.encoder, 'pdus'))")
    g.add("payload_queue", "snippet", coord,
          "the payload file -> PDUs of one TB each, queued before the start: TB s carries "
          "PDU s, padding-only TBs after the last (nrsar-isac's grid of the file)",
          section="main_after_init", priority="2", code=code)


def payload_strobe(g, comment):
    """The live graphs' backhaul payload: a 1000-byte PDU every 50 ms into the encoder."""
    g.add("payload_strobe", "blocks_message_strobe", (8, 420), comment,
          msg="pmt.cons(pmt.make_dict(), pmt.init_u8vector(1000, [i % 251 for i in range(1000)]))",
          period="50")


def uav_tx(g, x, y):
    g.var("max_queued_bytes", "1048576", (x, y - 100),
          "the encoder's PDU queue bound (a payload file is queued whole before the start)")
    g.add("encoder", "nrsar_pusch_encoder", (x, y),
          "TB per slot: MAC PDU, TS 38.212 UL-SCH (MCS 10 of the qam256 table: 16-QAM, "
          "R 0.64), 38.211 scrambling",
          numerology=NUM, modulation=QAM, dmrs="pusch2", dmrs_id="0", **PUSCH,
          max_queued_bytes="max_queued_bytes")
    g.add("tx", "nrsar_nr_isac_tx", (x + 240, y),
          "the UAV uplink grid: 16-QAM PUSCH data + DMRS {2, 11}; also the radar reference",
          numerology=NUM, num_subcarriers=N, modulation=QAM, mode="data", srs_start="0",
          srs_num_rb="24", srs_comb="4", srs_comb_offset="0", srs_period="2", srs_symbol="13",
          seed="0", dmrs="pusch2", dmrs_id="0")
    g.c("encoder", "0", "tx", "0")


def modulator(g, name, x, y):
    g.add(name, "nrsar_ofdm_mod", (x, y), "grid -> 30.72 Msps CP-OFDM samples",
          numerology=NUM, num_subcarriers=N)


def base_station(g, x, y, src, src_port="0", eq=False, channel=True):
    """[delay + channel_model] -> ofdm_sync -> ofdm_demod -> pusch_receiver -> PDU filter ->
    decoded file"""
    if channel:
        g.add("bs_delay", "blocks_delay", (x, y), "unknown propagation delay to the base station",
              type="complex", delay="bs_delay_samples", num_ports="1", vlen="1")
        g.add("bs_channel", "channels_channel_model", (x + 180, y),
              "UAV -> base station: noise (SNR per RE), CFO, multipath inside the CP",
              noise_voltage="10 ** (-bs_snr_db / 20.0)", freq_offset="bs_cfo_hz / samp_rate",
              epsilon="1.0", taps="[1.0, 0, 0, 0.2j]", seed="7", block_tags="False")
        g.c(src, src_port, "bs_delay", "0")
        g.c("bs_delay", "0", "bs_channel", "0")
        src, src_port = "bs_channel", "0"
    g.add("bs_sync", "nrsar_ofdm_sync", (x + 420, y),
          "Schmidl & Cox on the DMRS: slot timing and CFO; tags slot 0 = the burst's first slot",
          numerology=NUM, dmrs="'pusch2'", threshold="0.1", backoff="0.125")
    g.add("bs_demod", "nrsar_ofdm_demod", (x + 620, y), "", numerology=NUM,
          num_subcarriers=N, fft_start="-1", tx_start_time="-1")
    g.add("bs_rx", "nrsar_pusch_receiver", (x + 820, y),
          "DMRS channel estimate, ZF equaliser, soft demapper, NR LDPC, CRCs: one PDU per TB",
          numerology=NUM, num_subcarriers=N, modulation=QAM, dmrs="pusch2", dmrs_id="0",
          **PUSCH, freq_window="3", max_iterations="8",
          show_eq="True" if eq else "False")
    g.add("not_filler", "pdu_pdu_filter", (x + 820, y + 140), "drop filler TBs",
          k='pmt.intern("filler")', v="pmt.PMT_F", invert="False")
    g.add("crc_ok", "pdu_pdu_filter", (x + 820, y + 220),
          "keep CRC-checked TBs (failed ones carry no data anyway)",
          k='pmt.intern("crc_ok")', v="pmt.PMT_T", invert="False")
    g.add("to_bytes", "pdu_pdu_to_tagged_stream", (x + 1040, y + 220), "", type="byte",
          tag="packet_len")
    g.add("decoded_sink", "blocks_file_sink", (x + 1240, y + 220),
          "the decoded payload, byte for byte the file sent when every TB arrived",
          file="decoded", type="byte", vlen="1", unbuffered="False", append="False")
    g.c(src, src_port, "bs_sync", "0")
    g.c("bs_sync", "0", "bs_demod", "0")
    g.c("bs_demod", "0", "bs_rx", "0")
    g.c("bs_rx", "pdus", "not_filler", "pdus")
    g.c("not_filler", "pdus", "crc_ok", "pdus")
    g.c("crc_ok", "pdus", "to_bytes", "pdus")
    g.c("to_bytes", "0", "decoded_sink", "0")


def radar(g, x, y, rx_src, rx_port, ref_src, echo=True, tx_start="-1", sync_demod=False):
    """[td_echo] -> [ofdm_sync] -> ofdm_demod -> imaging_chain (tf_filter(grid) -> range_ifft
    -> cheby_presum -> rd_focuser -> nmse_probe, built by nrsar.chain as in nrsar-sim)"""
    if echo:
        g.add("echo", "nrsar_td_echo", (x, y),
              "time-domain echo of a target 300 m off the track (per-symbol delay, Doppler)",
              numerology=NUM, geometry="short", scene=SCENE, beam_mode="whole_block",
              az_aperture="0.1", el_aperture="0.1", el_center_deg="45.0", noise="True",
              snr_db="radar_snr_db", seed="2", taps="32", kaiser_beta="-1.0")
        g.c(rx_src, rx_port, "echo", "0")
        rx_src, rx_port = "echo", "0"
    if sync_demod:
        g.add("radar_sync", "nrsar_ofdm_sync", (x + 200, y - 100),
              "no rx_time from this front end: the TX->RX leakage (range 0) sets symbol 0",
              numerology=NUM, dmrs="'pusch2'", threshold="0.1", backoff="0.0")
        g.c(rx_src, rx_port, "radar_sync", "0")
        rx_src, rx_port = "radar_sync", "0"
    g.add("radar_demod", "nrsar_ofdm_demod", (x + 200, y),
          "rx_time alignment on: the first output is symbol 0" if tx_start != "-1" else "",
          numerology=NUM, num_subcarriers=N, fft_start="-1", tx_start_time=tx_start)
    g.add("imaging", "nrsar_imaging_chain", (x + 400, y),
          "nrsar-sim's receive chain (nrsar.imaging_chain): Wiener filter against the known "
          "grid, range IFFT, Chebyshev presummer, RD focuser, NMSE probe on its PSF model",
          preset="sdr20", geometry="short", scene="300,2", modulation=QAM, filter="wf",
          snr_db="radar_snr_db", presum="cheby", decim="decim", reference="False")
    g.add("range_null", "blocks_null_sink", (x + 640, y + 100),
          "the range-compressed data (imaging output 1) is not kept here",
          type="complex", vlen="chain_layout.range_bins", num_inputs="1",
          bus_structure_sink="[[0,],]")
    g.c(rx_src, rx_port, "radar_demod", "0")
    g.c("radar_demod", "0", "imaging", "0")
    g.c(ref_src, "0", "imaging", "1")
    g.c("imaging", "1", "range_null", "0")


def headless_sinks(g, x, y):
    g.add("metrics_print", "blocks_message_debug", (x, y), "NMSE, SNR_out, ... per aperture",
          en_uvec="True")
    g.add("image_sink", "blocks_file_sink", (x, y - 100),
          "focused image: complex64, range_bins per azimuth line", file="image",
          type="complex", vlen="range_bins", unbuffered="False", append="False")
    g.c("imaging", "metrics", "metrics_print", "print")
    g.c("imaging", "0", "image_sink", "0")


def headless_params(g, y=200, symbols="2400"):
    g.param("symbols", "OFDM symbols", symbols, (8, y), "intx", "one aperture of the short "
            "geometry at sdr20 (2400 symbols = 0.1 s)", "n")
    g.param("payload", "Payload file", "payload.bin", (160, y), "str", "", "p")
    g.param("decoded", "Decoded file", "decoded.bin", (320, y), "str", "", "d")
    g.param("image", "Image file (complex64)", "image.c64", (480, y), "str", "", "o")


def channel_params(g, y=300, gui=False):
    if gui:
        g.add("bs_snr_db", "variable_qtgui_range", (8, y), "", label="Base station SNR per RE [dB]",
              rangeType="float", value="25", start="0", stop="40", step="0.5",
              widget="counter_slider", orient="QtCore.Qt.Horizontal", min_len="200",
              gui_hint="0, 0, 1, 1")
        g.add("bs_cfo_hz", "variable_qtgui_range", (200, y), "", label="CFO [Hz]",
              rangeType="float", value="6000", start="-14000", stop="14000", step="100",
              widget="counter_slider", orient="QtCore.Qt.Horizontal", min_len="200",
              gui_hint="0, 1, 1, 1")
    else:
        g.param("bs_snr_db", "Base station SNR per RE (dB)", "30", (8, y), "eng_float", "", "")
        g.param("bs_cfo_hz", "Base station CFO (Hz)", "6000", (200, y), "eng_float", "", "")
    g.param("bs_delay_samples", "Base station delay (samples)", "1000", (400, y), "intx", "", "")
    g.param("radar_snr_db", "Radar SNR_in per RE (dB)", "10", (600, y), "eng_float", "", "")


def finite_uav_and_base_station(g):
    """payload file -> UAV TX -> head (finite run) -> ofdm_mod -> base station"""
    payload_queue(g, (8, 420))
    uav_tx(g, 200, 420)
    g.add("head", "blocks_head", (700, 420), "finite run", num_items="symbols",
          type="complex", vlen=N)
    modulator(g, "modulator", 880, 420)
    g.c("tx", "0", "head", "0")
    g.c("head", "0", "modulator", "0")
    base_station(g, 8, 640, "modulator")


# ---------------------------------------------------------------- the one graph, headless
def isac_headless():
    g = Graph("isac_backhaul_imaging_headless", "gr-nrsar ISAC: backhaul decode + imaging (headless)",
              "The one graph, headless: payload file -> pusch_encoder -> nr_isac_tx (DMRS) -> "
              "ofdm_mod; base station: delay + channel_model -> ofdm_sync -> ofdm_demod -> "
              "pusch_receiver -> decoded file; radar: td_echo -> ofdm_demod -> tf_filter -> "
              "range_ifft -> cheby_presum -> rd_focuser -> nmse_probe + image file. "
              "One aperture (0.1 s) at sdr20.", gui=False)
    common_vars(g)
    headless_params(g)
    channel_params(g)
    finite_uav_and_base_station(g)
    radar(g, 8, 960, "modulator", "0", "head")
    headless_sinks(g, 1400, 1100)
    g.dump()


# ---------------------------------------------------------------- the one graph, Qt GUI
def gui_sinks(g):
    g.add("const", "qtgui_const_sink_x", (1300, 900),
          "the base station's equalised 16-QAM data REs", type="complex",
          name_='"base station: equalised PUSCH symbols"', size="2048", grid="True",
          autoscale="False", ymin="-1.5", ymax="1.5", xmin="-1.5", xmax="1.5",
          nconnections="1", update_time="0.10", gui_hint="1, 0, 1, 1",
          tr_mode="qtgui.TRIG_MODE_FREE", tr_slope="qtgui.TRIG_MODE_POS", tr_level="0.0",
          tr_chan="0", tr_tag='""', legend="False", axislabels="True", label1='""',
          width1="1", color1='"blue"', style1="0", marker1="0", alpha1="1.0")
    g.c("bs_rx", "0", "const", "0")
    g.add("power", "blocks_complex_to_mag_squared", (1300, 1100), "", vlen="range_bins")
    g.add("to_db", "blocks_nlog10_ff", (1300, 1180), "", n="10", k="0", vlen="range_bins")
    g.add("to_stream", "blocks_vector_to_stream", (1300, 1260), "", type="float",
          num_items="range_bins", vlen="1")
    g.add("raster", "qtgui_time_raster_sink_x", (1500, 1200),
          "rows: azimuth lines of the focused aperture, columns: slant range 950 .. 1150 m",
          type="float", name_='"focused image [dB]"', samp_rate="24000 / decim * range_bins",
          nrows="aperture_symbols // decim", ncols="range_bins", x_label='"slant range [m]"',
          x_start_value="chain_layout.first_range_m",
          x_end_value="chain_layout.first_range_m + range_bins * chain_layout.range_bin_m",
          y_label='"azimuth line"', y_start_value="0", y_end_value="aperture_symbols // decim",
          grid="False", zmin="-30", zmax="45", mult="[]", offset="[]", nconnections="1",
          update_time="0.0", gui_hint="1, 1, 1, 1", axislabels="True", label1='""',
          color1="1", alpha1="1.0")
    g.c("imaging", "0", "power", "0")
    g.c("power", "0", "to_db", "0")
    g.c("to_db", "0", "to_stream", "0")
    g.c("to_stream", "0", "raster", "0")
    x = 8
    probes = [("nmse_val", "imaging", "nmse_db", "NMSE [dB]", "float", "2, 0, 1, 1"),
              ("snr_out_val", "imaging", "snr_out_db", "SNR_out [dB]", "float", "2, 1, 1, 1"),
              ("blocks_ok_val", "bs_rx", "blocks_ok", "TBs ok", "int", "3, 0, 1, 1"),
              ("blocks_failed_val", "bs_rx", "blocks_failed", "TBs failed", "int", "3, 1, 1, 1"),
              ("bs_snr_val", "bs_rx", "last_snr_db", "base-station SNR estimate [dB]", "float",
               "4, 0, 1, 1"),
              ("bytes_val", "bs_rx", "payload_bytes_ok", "payload bytes decoded", "int",
               "4, 1, 1, 1")]
    for i, (vid, blk, fn, label, typ, hint) in enumerate(probes):
        g.add(vid, "variable_function_probe", (x + 180 * i, 1400), "", block_id=blk,
              function_name=fn, function_args="", poll_rate="2", value="0")
        fmt = "lambda v: f'{v:.2f}'" if typ == "float" else "None"
        g.add(vid + "_label", "variable_qtgui_label", (x + 180 * i, 1500), "", label=label,
              type=typ if typ == "int" else "real", value=vid, formatter=fmt, gui_hint=hint)


def isac_gui():
    g = Graph("isac_backhaul_imaging", "gr-nrsar ISAC: backhaul decode + imaging (live)",
              "The one graph with a Qt GUI: the UAV's NR uplink (PDUs -> pusch_encoder -> "
              "nr_isac_tx -> ofdm_mod) decoded by the base station (channel_model with SNR and "
              "CFO sliders -> ofdm_sync -> ofdm_demod -> pusch_receiver: constellation, TB "
              "counts) and imaged by the UAV itself (td_echo -> ofdm_demod -> tf_filter -> "
              "range_ifft -> cheby_presum -> rd_focuser: live image, NMSE and SNR_out).",
              gui=True)
    common_vars(g)
    channel_params(g, gui=True)
    g.param("symbol_rate", "Symbols per second (throttle)", "4800", (8, 200), "eng_float",
            "24000 = real time at sdr20; lower it on a slow machine", "r")
    g.param("decoded", "Decoded file", "/dev/null", (200, 200), "str", "", "d")
    payload_strobe(g, "a 1000-byte PDU every 50 ms (20 kB/s of backhaul payload)")
    g.c("payload_strobe", "strobe", "encoder", "pdus")
    uav_tx(g, 200, 420)
    g.add("throttle", "blocks_throttle", (700, 420), "slow time at symbol_rate",
          type="complex", samples_per_second="symbol_rate", vlen=N, ignoretag="True")
    modulator(g, "modulator", 880, 420)
    g.c("tx", "0", "throttle", "0")
    g.c("throttle", "0", "modulator", "0")
    base_station(g, 8, 640, "modulator", eq=True)
    radar(g, 8, 960, "modulator", "0", "throttle")
    gui_sinks(g)
    g.dump()


def sdr_params(g, y=200):
    g.param("tx_start_s", "TX start (device time, s)", "1.0", (8, y), "eng_float",
            "the device clock is set to 0 at start-up; symbol 0 leaves the DAC at this time", "")
    g.param("rx_lead_s", "RX starts this much earlier (s)", "0.01", (200, y), "eng_float",
            "", "")
    g.param("hw_delay_samples", "TX->RX hardware delay (samples)", "0", (400, y), "intx",
            "calibrate with a loopback cable (docs/sdr.md)", "")
    g.param("freq", "Carrier (Hz)", "3.5e9", (600, y), "eng_float", "", "f")
    g.param("tx_gain", "TX gain (dB)", "30", (760, y), "eng_float", "", "")
    g.param("rx_gain", "RX gain (dB)", "30", (920, y), "eng_float", "", "")
    g.param("tx_scale", "TX amplitude scale", "0.3", (1080, y), "eng_float",
            "keeps the OFDM peaks below the DAC's full scale", "")
    g.param("radar_snr_db", "Radar SNR_in for the Wiener filter (dB)", "10", (1240, y),
            "eng_float", "", "")


def recorder(g, rx, coord, hw, delay, tx_async=None):
    """record_dir (default '' = off): the radar's receive stream as SigMF
    (nrsar.recording.sigmf_sink: rx_time tags -> overflow annotations; docs/recording.md),
    connected by a snippet only when a folder is given; the meta names the payload file
    (payload_queue's) and the encoder's PUSCH (isac_chain.graph_pusch of PUSCH, checked
    against the encoder block). tx_async: the UHD sink whose async_msgs a
    tx_underrun_counter counts into the meta (nrsar:tx_underruns)."""
    # PUSCH in IsacOptions' spelling (the first transmission's rv is pusch_meta's 0);
    # seed 0 below: nr_isac_tx's (nrsar:grid_seed)
    assert PUSCH["rv"] == "0"
    pusch_fields = ", ".join(
        f"{k}={v}" if v.isdigit() else f"{k}={v.replace('_', '-')!r}"
        for k, v in PUSCH.items() if k != "rv") + ", dmrs_id=0"
    counter = ("    self.tx_underruns = nrsar.recording.tx_underrun_counter()\n"
               f"    self.msg_connect((self.{tx_async}, 'async_msgs'), "
               "(self.tx_underruns, 'async_msgs'))\n") if tx_async else ""
    g.param("record_dir", "Record the RX stream as SigMF into (folder, '' = off)", "",
            (coord[0], coord[1] - 100), "str", "", "")
    g.add("record", "snippet", coord,
          "record_dir set: the RX stream -> DIR/flight.sigmf-{data,meta} (SigMF, the nrsar "
          "extension; overflows from rx_time become annotations)",
          section="main_after_init", priority="1",
          code="if self.record_dir:\n    from gnuradio.nrsar import isac_chain\n" + counter +
               "    self.recorder = nrsar.recording.sigmf_sink(\n"
               "        self.record_dir, nrsar.SimOptions(preset='sdr20', geometry='short', "
               f"scene='300,2', modulation='{QAM}', snr_db=self.radar_snr_db, seed=0),\n"
               f"        hardware_delay_s={delay}, hw='{hw}',\n"
               "        dmrs=nrsar.make_dmrs('pusch2').symbols, payload_path=self.payload_path,\n"
               f"        pusch=isac_chain.graph_pusch(self.encoder, '{NUM}', '{QAM}', 'pusch2', "
               f"{pusch_fields}) if self.payload_path else None,\n"
               f"        recorder='{g.gid}.grc (gr-nrsar)'"
               + (", tx_underruns=self.tx_underruns" if tx_async else "") + ")\n"
               f"    self.connect((self.{rx}, 0), (self.recorder, 0))")


def sdr_graph(gid, title, description, front_end):
    g = Graph(gid, title, description, gui=True)
    common_vars(g)
    sdr_params(g)
    g.param("decoded", "Decoded file", "/dev/null", (8, 300), "str", "", "d")
    g.param("payload", "Payload file ('strobe' = a live PDU strobe, not recorded)",
            "/usr/share/common-licenses/GPL-3", (200, 300), "str",
            "sent once from the first slot, then padding-only TBs; recorded by name and "
            "SHA-256, so nrsar-process regenerates the grid", "p")
    payload_queue(g, (1240, 460), strobe=True)
    uav_tx(g, 200, 420)
    modulator(g, "modulator", 700, 420)
    g.add("tx_level", "blocks_multiply_const_vxx", (880, 420), "", type="complex",
          const="tx_scale", vlen="1")
    g.c("tx", "0", "modulator", "0")
    g.c("modulator", "0", "tx_level", "0")
    if front_end == "uhd":
        g.add("usrp_sink", "uhd_usrp_sink", (1080, 400),
              "timed start: the first sample leaves at tx_start_s (device time)",
              type="fc32", otw="", stream_args="", stream_chans="[]", dev_addr='""',
              dev_args='""', sync="none", start_time="tx_start_s", clock_rate="0e0",
              num_mboards="1", clock_source0="", time_source0="", sd_spec0="", nchan="1",
              samp_rate="samp_rate", center_freq0="freq", gain0="tx_gain",
              gain_type0="default", ant0='"TX/RX"', bw0="0", len_tag_name='""')
        g.add("usrp_source", "uhd_usrp_source", (8, 760),
              "timed start at tx_start_s - rx_lead_s; tags rx_time on its first sample and "
              "after every overflow", type="fc32", otw="", stream_args="", stream_chans="[]",
              dev_addr='""', dev_args='""', sync="none", start_time="tx_start_s - rx_lead_s",
              clock_rate="0e0", num_mboards="1", clock_source0="", time_source0="",
              sd_spec0="", nchan="1", samp_rate="samp_rate", center_freq0="freq",
              rx_agc0="Default", gain0="rx_gain", gain_type0="default", ant0='"RX2"',
              bw0="0", dc_offs_enb0='""', iq_imbal_enb0='""')
        g.add("clock_zero", "snippet", (1080, 560),
              "device time 0 just before the flowgraph starts (TX and RX share the device)",
              section="main_after_init", priority="0",
              code="self.usrp_sink.set_time_now(uhd.time_spec(0.0))")
        g.c("tx_level", "0", "usrp_sink", "0")
        rx = "usrp_source"
        tx_start = "tx_start_s + hw_delay_samples / samp_rate"
        sync_demod = False
    else:
        g.add("soapy_sink", "soapy_sink", (1080, 400), "", type="fc32", devname="uhd",
              dev='"driver=uhd"', args='""', samp_rate="samp_rate", nchan="1",
              clock_rate="0", clock_source='""', length_tag_name='""', center_freq0="freq",
              nco_freq0="0", manual_gain0="True", overall_gain0="tx_gain", ant0='"TX/RX"',
              bw0="0")
        g.add("soapy_source", "soapy_source", (8, 760),
              "gr-soapy sets no rx_time tag: the radar branch takes symbol 0 from the TX->RX "
              "leakage (ofdm_sync, no backoff)", nchan="1", devname="uhd",
              dev='"driver=uhd"', type="fc32", samp_rate="samp_rate", dev_args='""',
              stream_args='""', clock_rate="0", clock_source='""', tune_args0='""',
              settings0='""', center_freq0="freq", nco_freq0="0", gain_mode0="Overall",
              overall_gain0="rx_gain", ant0='"RX2"', bw0="0", dc_removal0="True",
              dc_offset0="0", correction0="0", balance0="0", agc0="False")
        g.c("tx_level", "0", "soapy_sink", "0")
        rx = "soapy_source"
        tx_start = "-1"
        sync_demod = True
    if front_end == "uhd":
        recorder(g, rx, (1240, 560), "USRP (gr-uhd), RX2",
                 "self.rx_lead_s + self.hw_delay_samples / self.samp_rate", tx_async="usrp_sink")
    else:  # no timed start: the recording starts wherever the source did
        recorder(g, rx, (1240, 560), "SoapySDR (gr-soapy), RX2", "0.0")
    base_station(g, 8, 900, rx, eq=True, channel=False)
    radar(g, 8, 1200, rx, "0", "tx", echo=False, tx_start=tx_start, sync_demod=sync_demod)
    gui_sinks(g)
    extra = [("sync_timing_val", "bs_sync", "timing_samples",
              "DMRS start in the RX stream [samples] (delay calibration, docs/sdr.md)", "int",
              "5, 0, 1, 1")]
    if front_end == "uhd":
        extra.append(("lost_val", "radar_demod", "lost_symbols", "radar symbols lost (overflow)",
                      "int", "5, 1, 1, 1"))
    for i, (vid, blk, fn, label, typ, hint) in enumerate(extra):
        g.add(vid, "variable_function_probe", (1100 + 180 * i, 1400), "", block_id=blk,
              function_name=fn, function_args="", poll_rate="2", value="0")
        g.add(vid + "_label", "variable_qtgui_label", (1100 + 180 * i, 1500), "", label=label,
              type=typ, value=vid, formatter="None", gui_hint=hint)
    g.dump()


STAMPER = '''"""rx_time stamper: what a USRP source adds to its samples (loopback stand-in)."""

import numpy as np
import pmt
from gnuradio import gr


class blk(gr.sync_block):
    """Tags the first sample with rx_time = (uint64 whole seconds, double fraction), the
    device time at which the (simulated) receiver started streaming."""

    def __init__(self, rx_start_s=0.99):
        gr.sync_block.__init__(self, name="rx_time stamper", in_sig=[np.complex64],
                               out_sig=[np.complex64])
        self.rx_start_s = rx_start_s

    def work(self, input_items, output_items):
        output_items[0][:] = input_items[0]
        if self.nitems_written(0) == 0 and len(output_items[0]) > 0:
            full = int(self.rx_start_s)
            self.add_item_tag(0, 0, pmt.intern("rx_time"),
                              pmt.make_tuple(pmt.from_uint64(full),
                                             pmt.from_double(self.rx_start_s - full)))
        return len(output_items[0])
'''


def loopback_headless():
    g = Graph("isac_loopback_headless", "gr-nrsar ISAC on a simulated USRP (loopback, headless)",
              "isac_usrp.grc with the radio replaced: TX samples -> td_echo (the scene) -> "
              "delay (RX lead + hardware delay) -> rx_time tag on the first sample, as a USRP "
              "source stamps it -> ofdm_demod aligned by tx_start_time; base station through "
              "channel_model. The image must equal isac_backhaul_imaging_headless's.", gui=False)
    common_vars(g)
    headless_params(g)
    g.params_done = True
    g.param("bs_snr_db", "Base station SNR per RE (dB)", "30", (8, 300), "eng_float", "", "")
    g.param("bs_cfo_hz", "Base station CFO (Hz)", "6000", (200, 300), "eng_float", "", "")
    g.param("bs_delay_samples", "Base station delay (samples)", "1000", (400, 300), "intx", "", "")
    g.param("radar_snr_db", "Radar SNR_in per RE (dB)", "10", (600, 300), "eng_float", "", "")
    g.param("tx_start_s", "TX start (device time, s)", "1.0", (800, 300), "eng_float", "", "")
    g.param("rx_lead_s", "RX starts this much earlier (s)", "0.01", (1000, 300), "eng_float",
            "", "")
    g.param("hw_delay_samples", "TX->RX hardware delay (samples)", "37", (1200, 300), "intx",
            "simulated fixed delay of the radio; the demodulator is told the same value", "")
    finite_uav_and_base_station(g)
    # the simulated radio: echo, then the RX's earlier start and the hardware delay
    g.add("echo", "nrsar_td_echo", (8, 900),
          "the scene (in place of the antenna and the ground)",
          numerology=NUM, geometry="short", scene=SCENE, beam_mode="whole_block",
          az_aperture="0.1", el_aperture="0.1", el_center_deg="45.0", noise="True",
          snr_db="radar_snr_db", seed="2", taps="32", kaiser_beta="-1.0")
    g.add("air", "blocks_tag_gate", (200, 900), "the air carries no stream tags",
          type="complex", vlen="1", propagate_tags="False", single_key='""')
    g.add("rx_latency", "blocks_delay", (360, 900),
          "the RX stream starts rx_lead_s before the TX; the radio adds hw_delay_samples",
          type="complex", delay="int(round(rx_lead_s * samp_rate)) + hw_delay_samples",
          num_ports="1", vlen="1")
    g.add("usrp_source", "epy_block", (560, 920),
          "stands in for the USRP source: stamps rx_time (uint64 s, double s) on the first "
          "sample, the way a USRP source tags its first sample",
          _source_code=STAMPER, rx_start_s="tx_start_s - rx_lead_s")
    g.c("modulator", "0", "echo", "0")
    g.c("echo", "0", "air", "0")
    g.c("air", "0", "rx_latency", "0")
    g.c("rx_latency", "0", "usrp_source", "0")
    radar(g, 8, 1100, "usrp_source", "0", "head", echo=False,
          tx_start="tx_start_s + hw_delay_samples / samp_rate")
    recorder(g, "usrp_source", (760, 820), "none: simulated USRP (td_echo, loopback graph)",
             "self.rx_lead_s + self.hw_delay_samples / self.samp_rate")
    headless_sinks(g, 1400, 1300)
    g.dump()


isac_headless()
isac_gui()
sdr_graph("isac_usrp", "gr-nrsar ISAC on a USRP (sdr20, 30.72 Msps)",
          "The one graph on a USRP (gr-uhd): TX and RX on one device, device time set to 0 "
          "at start-up, timed TX start at tx_start_s and RX start rx_lead_s earlier; the "
          "radar demodulator aligns to the TX start from the source's rx_time tag (plus the "
          "calibrated hardware delay); the base-station branch decodes the received stream "
          "(loopback cable or antenna). See docs/sdr.md.", "uhd")
sdr_graph("isac_soapy", "gr-nrsar ISAC on a SoapySDR radio (sdr20, 30.72 Msps)",
          "The one graph on a SoapySDR device (gr-soapy). gr-soapy has no timed start and no "
          "rx_time tag, so the radar branch takes symbol 0 from the TX->RX leakage with "
          "ofdm_sync (backoff 0); the base-station branch decodes the received stream. See "
          "docs/sdr.md.", "soapy")
loopback_headless()
