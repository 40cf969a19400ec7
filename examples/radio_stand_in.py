#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Runs an ISAC radio graph (grcc's isac_usrp.py or isac_soapy.py, unchanged) with its radio
replaced and checks its recording: the sink takes the TX samples; the source plays the
loopback's recording (isac_loopback_headless.py --record-dir, its RX stream). The graph's own
payload and record snippets run as in a flight (main_after_init, then start).

usrp: the source starts where the loopback's did (10 ms before the TX) and tags its first
sample rx_time as a USRP source does; the sink has the async_msgs port and posts nothing. A
tap on the imaging chain keeps the focused aperture. Fails unless the graph's image and
nrsar-process's image of the graph's recording both equal the loopback's image bit for bit
(the USRP graph's grid, the loopback's and build_transmitter's of the recorded meta are one
grid) and the meta names the payload, the PUSCH and 0 transmit underruns. Then with payload
'strobe': the live strobe's PDUs are encoded, the meta names no payload and nrsar-process
refuses the recording.

soapy: gr-soapy has no timed start, no rx_time tag and no underrun port, so the graph records
from wherever its source started (nrsar:hardware_delay_s 0) and cannot count underruns
(nrsar:tx_underruns null). The source starts at the loopback's symbol 0 (its recording's
hardware delay later), untagged. Fails unless nrsar-process's image of the graph's recording
equals the loopback's bit for bit, the meta names the payload and the PUSCH, nrsar-process
reports tx_underruns null without an underrun warning, and the radar's ofdm_sync put symbol 0
on the strongest DMRS path, the target's echo (a loopback recording has no TX -> RX leakage):
the target's round trip at the aperture's start within a sample. The graph's own image then has
the target at range 0, outside the image's swath (on a radio the leakage is the range 0).

usage: radio_stand_in.py {usrp,soapy} GRAPH_PY LOOPBACK_DIR OUT_DIR
  GRAPH_PY: isac_usrp.py / isac_soapy.py (grcc's output)
  LOOPBACK_DIR: payload.bin, rec/flight.sigmf-{meta,data} and image_rec.c64 of the loopback"""

import importlib.util
import json
import math
import os
import subprocess
import sys
import time
import types

import numpy as np
import pmt
from gnuradio import blocks, gr, uhd
from gnuradio.nrsar import recording
from PyQt5 import Qt

APPS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "apps")
HW_DELAY = 37  # the loopback's simulated TX -> RX delay [samples]
BINS = 32  # range bins per image line (chain_layout.image_bins of the ISAC graphs)
FS = 30.72e6  # sdr20's sample rate
C = 299792458.0
TX_START_S, RX_LEAD_S = 1.0, 0.01  # the USRP graph's defaults, as the loopback's


class radio_settings:
    """The radio's tuning calls (set_gain, ...; gr-soapy's template also asks has_* and
    list_antennas) have nothing to tune here (first among the bases: gr.hier_block2 has a
    __getattr__ of its own)."""

    def __getattr__(self, name):
        for prefix, value in (("set_", None), ("has_", False), ("list_", [])):
            if name.startswith(prefix):
                return lambda *args, **kwargs: value
        return super().__getattr__(name)


def sink_of(async_msgs):
    """The TX stand-in; async_msgs: the USRP sink's message port (gr-soapy's has none)."""
    class radio_sink(radio_settings, gr.sync_block):
        def __init__(self, *args, **kwargs):
            gr.sync_block.__init__(self, "radio sink stand-in", [np.complex64], None)
            if async_msgs:
                self.message_port_register_out(pmt.intern("async_msgs"))

        def work(self, input_items, output_items):
            return len(input_items[0])
    return radio_sink


def source_of(data_path, offset, t0):
    """The RX stand-in: the recording from sample offset on; t0: the rx_time tag of its first
    sample (None: untagged)."""
    class radio_source(radio_settings, gr.hier_block2):
        def __init__(self, *args, **kwargs):
            gr.hier_block2.__init__(self, "radio source stand-in", gr.io_signature(0, 0, 0),
                                    gr.io_signature(1, 1, gr.sizeof_gr_complex))
            # held here: a Python block whose object is collected crashes its thread
            self.file = blocks.file_source(gr.sizeof_gr_complex, data_path, False, offset, 0)
            chain = [self.file]
            if t0 is not None:
                self.stamper = recording.rx_time_stamper(FS, [], t0)
                chain.append(self.stamper)
            self.connect(*chain, self)
    return radio_source


def build(radio, graph, data, offset, payload, rec_dir):
    """The graph's top block with its radio replaced by stand-ins."""
    if radio == "usrp":
        graph.uhd = types.SimpleNamespace(usrp_sink=sink_of(True),
                                          usrp_source=source_of(data, 0, TX_START_S - RX_LEAD_S),
                                          stream_args=uhd.stream_args, time_spec=uhd.time_spec)
        return graph.isac_usrp(tx_start_s=TX_START_S, rx_lead_s=RX_LEAD_S,
                               hw_delay_samples=HW_DELAY, payload=payload, record_dir=rec_dir)
    graph.soapy = types.SimpleNamespace(sink=sink_of(False), source=source_of(data, offset, None))
    return graph.isac_soapy(payload=payload, record_dir=rec_dir)


def run(radio, graph, loop, out, payload):
    """graph (the module of GRAPH_PY) with its radio replaced, payload and record_dir out/rec;
    returns (top block, the tapped image, the meta's global, nrsar-process's run)."""
    data = os.path.join(loop, "rec", "flight.sigmf-data")
    with open(os.path.join(loop, "rec", "flight.sigmf-meta")) as f:
        loop_delay_s = json.load(f)["global"]["nrsar:hardware_delay_s"]
    offset = round(loop_delay_s * FS) if radio == "soapy" else 0  # soapy: from symbol 0
    samples = os.path.getsize(data) // 8 - offset
    rec_dir = os.path.join(out, "rec")
    tb = build(radio, graph, data, offset, payload, rec_dir)
    tap = blocks.vector_sink_c(BINS)
    tb.connect((tb.imaging, 0), tap)
    graph.snippets_main_after_init(tb)
    tb.start()
    deadline = time.monotonic() + 240

    def running():  # soapy: its image (the echo at range 0, outside the swath) is not waited for
        return (tb.recorder.nitems_read(0) < samples
                or (tap.nitems_read(0) < 240 if radio == "usrp" else not tb.radar_sync.locked())
                or payload == "strobe" and tb.encoder.payload_bytes_sent() == 0)
    # (the strobe's first PDU leaves 50 ms after the start: waited for, not assumed)
    while running() and time.monotonic() < deadline:
        time.sleep(0.1)
    tb.stop()
    tb.wait()
    with open(os.path.join(rec_dir, "flight.sigmf-meta")) as f:
        glob = json.load(f)["global"]
    proc = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-process"),
                           os.path.join(rec_dir, "flight.sigmf-meta"), "--snr-db", "10",
                           "--presum", "cheby", "--decim", "10", "--quiet", "--json",
                           "--out", os.path.join(out, "proc")], capture_output=True, text=True)
    print(f"{radio}, payload {payload!r}: image {tap.nitems_read(0)} lines, "
          f"{tb.recorder.nitems_read(0)} samples recorded; nrsar-process exit "
          f"{proc.returncode} {proc.stderr.strip()}")
    return tb, np.array(tap.data(), np.complex64).reshape(-1, BINS), glob, proc


def echo_delay_samples(glob):
    """The reference target's round trip at the aperture's start [samples] (float64)."""
    geo, target = glob["nrsar:geometry"], glob["nrsar:reference_target"]
    slant_m = math.hypot(target["x_m"], target["y_m"] - geo["track_start_m"], geo["height_m"])
    return 2 * slant_m / C * FS


def main(argv):
    if len(argv) != 4 or argv[0] not in ("usrp", "soapy"):
        print(__doc__)
        return 2
    radio, graph_py, loop, out = argv
    spec = importlib.util.spec_from_file_location(f"isac_{radio}", graph_py)
    graph = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(graph)
    qapp = Qt.QApplication([])  # noqa: F841 (the graph's widgets need one)
    loop_image = np.fromfile(os.path.join(loop, "image_rec.c64"), np.complex64)
    loop_image = loop_image.reshape(-1, BINS)
    with open(os.path.join(loop, "rec", "flight.sigmf-meta")) as f:
        loop_glob = json.load(f)["global"]
    tb, image, glob, proc = run(radio, graph, loop, os.path.join(out, "file"),
                                os.path.join(loop, "payload.bin"))
    result = json.loads(proc.stdout) if proc.returncode == 0 else {}
    checks = {
        "nrsar-process exit 0": proc.returncode == 0,
        "nrsar-process's image == the loopback's": proc.returncode == 0 and np.array_equal(
            np.load(result["image_npy"]), loop_image),
        "core:recorder": glob["core:recorder"] == f"isac_{radio}.grc (gr-nrsar)",
    }
    for key in ("nrsar:pusch", "nrsar:payload_sha256", "nrsar:payload_path", "nrsar:dmrs"):
        checks[f"{key} == the loopback's"] = glob[key] == loop_glob[key]
    if radio == "usrp":
        checks.update({
            "the graph's image == the loopback's": np.array_equal(image, loop_image),
            "nrsar:tx_underruns == 0": glob["nrsar:tx_underruns"] == 0,
            "nrsar:hardware_delay_s == the loopback's":
                glob["nrsar:hardware_delay_s"] == loop_glob["nrsar:hardware_delay_s"],
        })
    else:
        start, delay = tb.radar_sync.start_samples(), echo_delay_samples(glob)
        checks.update({
            "nrsar:hardware_delay_s == 0": glob["nrsar:hardware_delay_s"] == 0,
            "nrsar:tx_underruns null, nrsar-process's tx_underruns null, no underrun warning":
                glob["nrsar:tx_underruns"] is None and result.get("tx_underruns", 0) is None
                and not any("underran" in w for w in result.get("warnings", [])),
            f"radar symbol 0 = the echo: ofdm_sync start {start} within 1 of {delay:.2f}":
                abs(start - delay) < 1,
        })
        return report(checks)
    # payload 'strobe': the live strobe's 1000-byte PDUs (one per TB), nothing recorded
    tb, _, glob, proc = run(radio, graph, loop, os.path.join(out, "strobe"), "strobe")
    sent = tb.encoder.payload_bytes_sent()
    checks.update({
        f"strobe: PDUs of 1000 bytes encoded ({sent} bytes)": sent > 0 and sent % 1000 == 0,
        "strobe: nrsar:payload_sha256, nrsar:pusch null":
            glob["nrsar:payload_sha256"] is None and glob["nrsar:pusch"] is None,
        "strobe: nrsar-process refuses (exit 2, one line)":
            proc.returncode == 2 and "nrsar:payload_sha256 is null" in proc.stderr
            and len(proc.stderr.strip().splitlines()) == 1,
    })
    return report(checks)


def report(checks):
    for name, ok in checks.items():
        print(f"{'ok  ' if ok else 'FAIL'} {name}")
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
