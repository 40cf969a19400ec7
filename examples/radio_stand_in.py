#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""Runs isac_usrp.py (grcc's output, unchanged) with its USRP replaced and checks its
recording: the sink takes the TX samples and posts no async messages; the source plays
the loopback's recording (isac_loopback_headless.py --record-dir, its RX stream) with the
rx_time tag a USRP source puts on its first sample. The graph's own payload and record
snippets run as in a flight (main_after_init, then start); a tap on its imaging chain keeps
the focused aperture. Fails unless the graph's image and nrsar-process's image of the graph's
recording both equal the loopback's image bit for bit (the USRP graph's grid, the loopback's
and build_transmitter's of the recorded meta are one grid) and the meta names the payload,
the PUSCH and 0 transmit underruns. Then with payload 'strobe': the live strobe's PDUs are
encoded, the meta names no payload and nrsar-process refuses the recording.

usage: radio_stand_in.py ISAC_USRP_PY LOOPBACK_DIR OUT_DIR
  LOOPBACK_DIR: payload.bin, rec/flight.sigmf-{meta,data} and image_rec.c64 of the loopback"""

import importlib.util
import json
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


class radio_settings:
    """The USRP's tuning calls (set_gain, set_start_time, ...) have nothing to tune here
    (first among the bases: gr.hier_block2 has a __getattr__ of its own)."""

    def __getattr__(self, name):
        if name.startswith("set_"):
            return lambda *args, **kwargs: None
        return super().__getattr__(name)


class usrp_sink(radio_settings, gr.sync_block):
    def __init__(self, *args, **kwargs):
        gr.sync_block.__init__(self, "usrp_sink stand-in", [np.complex64], None)
        self.message_port_register_out(pmt.intern("async_msgs"))

    def work(self, input_items, output_items):
        return len(input_items[0])


def source_of(data_path, t0):
    class usrp_source(radio_settings, gr.hier_block2):
        def __init__(self, *args, **kwargs):
            gr.hier_block2.__init__(self, "usrp_source stand-in", gr.io_signature(0, 0, 0),
                                    gr.io_signature(1, 1, gr.sizeof_gr_complex))
            fs = 30.72e6
            # held here: a Python block whose object is collected crashes its thread
            self.file = blocks.file_source(gr.sizeof_gr_complex, data_path, False)
            self.stamper = recording.rx_time_stamper(fs, [], t0)
            self.connect(self.file, self.stamper, self)
    return usrp_source


def run(graph, loop, out, payload):
    """graph (the module of isac_usrp.py) with its USRP replaced, payload and record_dir out/rec;
    returns (top block, the tapped image, the meta's global, nrsar-process's run)."""
    data = os.path.join(loop, "rec", "flight.sigmf-data")
    samples = os.path.getsize(data) // 8
    tx_start_s, rx_lead_s = 1.0, 0.01  # the graph's defaults, as the loopback's
    graph.uhd = types.SimpleNamespace(usrp_sink=usrp_sink,
                                      usrp_source=source_of(data, tx_start_s - rx_lead_s),
                                      stream_args=uhd.stream_args, time_spec=uhd.time_spec)
    rec_dir = os.path.join(out, "rec")
    tb = graph.isac_usrp(tx_start_s=tx_start_s, rx_lead_s=rx_lead_s,
                         hw_delay_samples=HW_DELAY, payload=payload, record_dir=rec_dir)
    tap = blocks.vector_sink_c(BINS)
    tb.connect((tb.imaging, 0), tap)
    graph.snippets_main_after_init(tb)
    tb.start()
    deadline = time.monotonic() + 240
    # (the strobe's first PDU leaves 50 ms after the start: waited for, not assumed)
    while (tb.recorder.nitems_read(0) < samples or tap.nitems_read(0) < 240
           or payload == "strobe" and tb.encoder.payload_bytes_sent() == 0) \
            and time.monotonic() < deadline:
        time.sleep(0.1)
    tb.stop()
    tb.wait()
    with open(os.path.join(rec_dir, "flight.sigmf-meta")) as f:
        glob = json.load(f)["global"]
    proc = subprocess.run([sys.executable, os.path.join(APPS, "nrsar-process"),
                           os.path.join(rec_dir, "flight.sigmf-meta"), "--snr-db", "10",
                           "--presum", "cheby", "--decim", "10", "--quiet", "--json",
                           "--out", os.path.join(out, "proc")], capture_output=True, text=True)
    print(f"payload {payload!r}: image {tap.nitems_read(0)} lines, "
          f"{tb.recorder.nitems_read(0)} samples recorded; nrsar-process exit "
          f"{proc.returncode} {proc.stderr.strip()}")
    return tb, np.array(tap.data(), np.complex64).reshape(-1, BINS), glob, proc


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    graph_py, loop, out = argv
    spec = importlib.util.spec_from_file_location("isac_usrp", graph_py)
    graph = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(graph)
    qapp = Qt.QApplication([])  # noqa: F841 (the graph's widgets need one)
    loop_image = np.fromfile(os.path.join(loop, "image_rec.c64"), np.complex64)
    loop_image = loop_image.reshape(-1, BINS)
    with open(os.path.join(loop, "rec", "flight.sigmf-meta")) as f:
        loop_glob = json.load(f)["global"]
    tb, image, glob, proc = run(graph, loop, os.path.join(out, "file"),
                                os.path.join(loop, "payload.bin"))
    checks = {
        "the graph's image == the loopback's": np.array_equal(image, loop_image),
        "nrsar-process exit 0": proc.returncode == 0,
        "nrsar-process's image == the loopback's": proc.returncode == 0 and np.array_equal(
            np.load(json.loads(proc.stdout)["image_npy"]), loop_image),
        "core:recorder": glob["core:recorder"] == "isac_usrp.grc (gr-nrsar)",
        "nrsar:tx_underruns == 0": glob["nrsar:tx_underruns"] == 0,
    }
    for key in ("nrsar:pusch", "nrsar:payload_sha256", "nrsar:payload_path", "nrsar:dmrs",
                "nrsar:hardware_delay_s"):
        checks[f"{key} == the loopback's"] = glob[key] == loop_glob[key]
    # payload 'strobe': the live strobe's 1000-byte PDUs (one per TB), nothing recorded
    tb, _, glob, proc = run(graph, loop, os.path.join(out, "strobe"), "strobe")
    sent = tb.encoder.payload_bytes_sent()
    checks.update({
        f"strobe: PDUs of 1000 bytes encoded ({sent} bytes)": sent > 0 and sent % 1000 == 0,
        "strobe: nrsar:payload_sha256, nrsar:pusch null":
            glob["nrsar:payload_sha256"] is None and glob["nrsar:pusch"] is None,
        "strobe: nrsar-process refuses (exit 2, one line)":
            proc.returncode == 2 and "nrsar:payload_sha256 is null" in proc.stderr
            and len(proc.stderr.strip().splitlines()) == 1,
    })
    for name, ok in checks.items():
        print(f"{'ok  ' if ok else 'FAIL'} {name}")
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
