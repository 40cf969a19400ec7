#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""nrsar-isac end to end (sdr20, short apertures): the payload file crosses the backhaul
bit-exactly through CFO, timing offset and multipath; failed CRCs are reported and never
written; the time-domain radar path gives the TF-domain path's image; the JSON contract.

References are independent of the code under test: the payload file itself (numpy PRBS),
its split into slot-sized pieces (pusch_encoder.md: P = floor((G - 24) / 8) - 5 bytes), the
true CFO / delay given to channel_model, and the TF-domain image of nrsar-sim's chain."""

import json
import os
import subprocess
import sys
import tempfile
from unittest import mock

import numpy as np

from gnuradio import gr_unittest
from gnuradio.nrsar import chain, isac_chain, scenario
from gnuradio.nrsar.options import IsacOptions, parse_taps

APP = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "apps",
                   "nrsar-isac")

DELTA_F = 30e3  # sdr20 subcarrier spacing


def parse(argv):
    return IsacOptions.parse(argv)


def nmse_db(a, b):
    return 10 * np.log10(np.sum(np.abs(a - b) ** 2) / np.sum(np.abs(b) ** 2))


class qa_isac(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="qa_isac_")
        cls.payload = os.path.join(cls.dir, "payload.bin")
        rng = np.random.default_rng(5)
        cls.data = rng.integers(0, 256, 30000, dtype=np.uint8).tobytes()
        with open(cls.payload, "wb") as f:
            f.write(cls.data)
        from gnuradio import nrsar
        num = nrsar.make_numerology("sdr20")
        cls.symbol_len = num.cp_samples + num.fft_size
        cls.fs = num.fft_size * DELTA_F
        g = nrsar.pusch_slot_bits(num, nrsar.make_modulation("qam256"), nrsar.make_dmrs("pusch2"))
        # uncoded TB of (G - 24) / 8 bytes, less the MAC subheader and the RLC header
        # (pusch_encoder.md)
        cls.per_slot = (g - 24) // 8 - 4
        cls.g = g

    def run_isac(self, extra, name):
        out = os.path.join(self.dir, name)
        args = parse(["--preset", "sdr20", "--aperture-s", "0.05", "--scene", "single",
                      "--radar-domain", "tf", "--payload", self.payload, "--out", out] + extra)
        return isac_chain.run(args)

    def test_001_bit_exact_loopback_cfo_timing_multipath(self):
        rng = np.random.default_rng(11)
        delay = int(rng.integers(0, 20000))
        cfo = 0.3 * DELTA_F
        # 50 dB: the taps' notch (|H| down to 0.36) leaves ~41 dB on its subcarriers, enough
        # for uncoded 256-QAM TBs of 58,000 bits (at 40 dB about 1 TB in 8 failed there)
        r = self.run_isac(["--coding", "none", "--bs-snr-db", "50", "--cfo-hz", str(cfo),
                           "--delay-samples", str(delay), "--taps", "1,0,0.4-0.2j,0,0,0.15j"],
                          "loop")
        self.assertTrue(r["payload_identical"])
        with open(r["decoded_file"], "rb") as f:
            self.assertEqual(f.read(), self.data)
        self.assertEqual(r["decoded_bytes"], len(self.data))
        self.assertEqual(r["payload_slots"], -(-len(self.data) // self.per_slot))
        self.assertEqual(r["backhaul_ber"], 0.0)
        self.assertEqual(r["blocks_failed"], 0)
        self.assertEqual(r["backhaul_bler"], 0.0)
        self.assertGreaterEqual(r["blocks_ok"], r["payload_slots"])
        self.assertLess(abs(r["sync_cfo_hz"] - cfo), 0.01 * DELTA_F)
        # first DMRS symbol (pusch2: symbol 2) after the delay; channel_model's own
        # offset and the taps' spread (5 samples) are a few samples
        self.assertLess(abs(r["sync_timing_samples"] - (delay + 2 * self.symbol_len)), 16)
        # delivered bits over the payload slots' air time (slot = 14 symbols of cp + F)
        slot_s = 14 * self.symbol_len / self.fs
        self.assertAlmostEqual(r["throughput_mbps"],
                               8 * len(self.data) / (r["payload_slots"] * slot_s) / 1e6, 6)

    def test_002_crc_failures_reported_never_written(self):
        # 256-QAM uncoded at 14 dB: the sync still locks (DMRS), every TB fails its CRC
        r = self.run_isac(["--coding", "none", "--bs-snr-db", "14"], "low")
        self.assertFalse(r["payload_identical"])
        self.assertGreater(r["blocks_failed"], 0)
        self.assertEqual(r["blocks_ok"], 0)
        self.assertEqual(r["backhaul_bler"], 1.0)
        self.assertEqual(r["decoded_bytes"], 0)
        self.assertEqual(os.path.getsize(r["decoded_file"]), 0)
        self.assertEqual(r["backhaul_ber"], 1.0)
        # in between: what is written is exactly the payload pieces of the slots that passed
        r = self.run_isac(["--coding", "none", "--bs-snr-db", "33", "--taps", "1"], "mid")
        self.assertGreater(r["blocks_ok"], 0)  # a mix (seeded: 44 ok, 41 failed)
        self.assertGreater(r["blocks_failed"], 0)
        failed = set(r["failed_payload_slots"])
        pieces = [self.data[i:i + self.per_slot] for i in range(0, len(self.data), self.per_slot)]
        expect = b"".join(p for s, p in enumerate(pieces) if s not in failed)
        with open(r["decoded_file"], "rb") as f:
            self.assertEqual(f.read(), expect)
        lost = sum(len(p) for s, p in enumerate(pieces) if s in failed)
        self.assertAlmostEqual(r["backhaul_ber"], lost / len(self.data), 12)
        self.assertEqual(r["payload_identical"], not failed)
        print(f"33 dB: {r['blocks_failed']} of {r['blocks_ok'] + r['blocks_failed']} TBs "
              f"failed, {len(failed)} of {len(pieces)} payload slots")

    def test_003_time_domain_image_matches_tf_domain(self):
        images, results = {}, {}
        for domain in ("time", "tf"):
            for snr in ("200", "-20"):
                out = os.path.join(self.dir, f"img_{domain}_{snr}")
                r = isac_chain.run(parse(["--preset", "sdr20", "--aperture-s", "0.2", "--scene",
                                    "single", "--snr-db", snr, "--radar-domain", domain,
                                    "--payload", self.payload, "--seed", "3", "--out", out]))
                results[domain, snr] = r
                images[domain, snr] = np.load(r["image_npy"])
        for snr, tol in (("200", 0.01), ("-20", 1.0)):
            td, tf = results["time", snr], results["tf", snr]
            print(f"SNR {snr} dB: NMSE time {td['nmse_db']:.3f} dB, tf {tf['nmse_db']:.3f} dB, "
                  f"image difference {nmse_db(images['time', snr], images['tf', snr]):.1f} dB")
            # 200 dB (noise off in effect): the same image, NMSE within 0.001 dB (the issue
            # asks 0.1 dB). At 60 dB the two noise draws alone move NMSE by ~0.05 dB through
            # the cross term of the error with the -98 dB noise image (as two seeds of one
            # path do). -20 dB: td_echo and scene_echo draw different noise; in a 0.2 s aperture
            # the scene's Doppler band keeps ~7 independent azimuth samples per range bin, so
            # NMSE moves by ~1 dB from seed to seed (measured 21.9-23.0 dB over 4 seeds, either
            # path): only agreement within that spread can be asked.
            self.assertLess(abs(td["nmse_db"] - tf["nmse_db"]), tol)
            self.assertEqual(td["range_axis_m"], tf["range_axis_m"])
            self.assertEqual(td["azimuth_axis_m"], tf["azimuth_axis_m"])
            self.assertLess(abs(td["peak_error_m"] - tf["peak_error_m"]), 0.1)
        # noise-free (200 dB) the two images are the same image (measured -141.7 dB)
        self.assertLess(nmse_db(images["time", "200"], images["tf", "200"]), -100)

    def test_007_same_noise_time_vs_tf_at_minus_20_db(self):
        # The 0.1 dB at the operating SNR: both paths get the same noise draw
        # (isac_chain.common_noise_front), so they differ only by the echo model.
        from gnuradio import gr
        args = parse(["--preset", "sdr20", "--aperture-s", "0.2", "--scene", "single",
                      "--snr-db", "-20", "--seed", "3"])
        sc = scenario.of(args)
        res = {}
        for domain in ("time", "tf"):
            tb = gr.top_block()
            graph = chain.build(tb, args, sc,
                                echo_front=isac_chain.common_noise_front(domain, 9))
            tb.run()
            k = graph["range_ifft"].num_bins()
            res[domain] = (graph["probe"].metrics()["nmse_db"],
                           np.asarray(graph["image_sink"].data()).reshape(-1, k))
        diff = nmse_db(res["time"][1], res["tf"][1])
        print(f"same noise, -20 dB: NMSE time {res['time'][0]:.4f} dB, tf {res['tf'][0]:.4f} "
              f"dB, image difference {diff:.1f} dB")
        self.assertLess(abs(res["time"][0] - res["tf"][0]), 0.1)
        self.assertLess(diff, -60)

    def test_004_json_contract_of_the_app(self):
        out = os.path.join(self.dir, "app")
        env = dict(os.environ)
        proc = subprocess.run([sys.executable, APP, "--preset", "sdr20", "--aperture-s", "0.05",
                               "--scene", "single", "--radar-domain", "tf", "--payload",
                               self.payload, "--out", out, "--json"],
                              capture_output=True, text=True, env=env, check=True)
        result = json.loads(proc.stdout.strip().splitlines()[-1])
        for key in ("nmse_db", "nmse_theory_db", "pel_db", "snr_out_db", "islr_db", "pslr_db",
                    "irw_range_m", "irw_azimuth_m", "peak_error_m", "image_npy", "image_png",
                    "range_axis_m", "azimuth_axis_m", "runtime_s", "rx_runtime_s",
                    "peak_rss_mb", "payload_identical", "payload_bytes", "decoded_bytes",
                    "backhaul_ber", "backhaul_bler", "blocks_ok", "blocks_failed",
                    "throughput_mbps", "code_rate", "sync_cfo_hz", "sync_timing_samples"):
            self.assertIn(key, result)
        self.assertTrue(result["payload_identical"])
        for key in ("coding", "mcs", "tbs_bits", "code_blocks", "ldpc_iterations_mean"):
            self.assertIn(key, result)
        # a clean link: no gap, no lock lost (docs/isac.md, the sync_* keys)
        for key in ("blocks_lost", "sync_lost_samples", "sync_rx_time_gaps", "sync_lock_losses",
                    "sync_reacquisitions", "sync_skipped_slots", "sync_skipped_symbols"):
            self.assertEqual(result[key], 0, key)
        self.assertEqual((result["coding"], result["mcs"]), ("nr-ldpc", 27))
        self.assertTrue(os.path.isfile(os.path.join(out, "decoded.bin")))
        self.assertTrue(os.path.isfile(result["image_png"]))

    def test_006_ldpc_loopback(self):
        # 256-QAM at 25 dB: uncoded TBs fail, the UL-SCH at qam256 MCS 20 (R 682.5/1024)
        # delivers the file
        r = self.run_isac(["--coding", "none", "--bs-snr-db", "25"], "uncoded25")
        self.assertGreater(r["blocks_failed"], 0)
        threads = str(min(2, os.cpu_count() or 1))  # the code blocks on two threads where it can
        r = self.run_isac(["--mcs", "20", "--bs-snr-db", "25", "--rx-threads", threads], "ldpc")
        self.assertTrue(r["payload_identical"])
        self.assertEqual(r["blocks_failed"], 0)
        g = self.g
        # 38.214 5.1.3.2 on 51 PRB x 144 REs: N_info = 7344 x 682.5/1024 x 8 = 39159,
        # n = 10, N'_info = 1024 round(39135 / 1024) = 38912, C = ceil(38936 / 8424) = 5,
        # TBS = 40 ceil(38936 / 40) - 24 = 38936
        self.assertEqual(r["tbs_bits"], 38936)
        self.assertEqual(r["code_blocks"], 5)
        self.assertAlmostEqual(r["code_rate"], (38936 + 24) / g, 12)
        self.assertEqual(r["mcs"], 20)
        self.assertGreaterEqual(r["ldpc_iterations_mean"], 1.0)

    def test_005_invalid_arguments(self):
        big = os.path.join(self.dir, "big.bin")
        with open(big, "wb") as f:
            f.write(bytes(10 * 1024 * 1024))
        with self.assertRaisesRegex(ValueError, "need .* slots, the aperture has"):
            isac_chain.run(parse(["--preset", "sdr20", "--aperture-s", "0.05", "--payload", big,
                            "--out", os.path.join(self.dir, "x")]))
        with self.assertRaisesRegex(ValueError, "--mode = 'srs2' must be data"):
            parse(["--preset", "sdr20", "--mode", "srs2", "--payload", self.payload])
        with self.assertRaisesRegex(ValueError, "--taps = '0,0' must hold"):
            parse_taps("0,0")
        with self.assertRaisesRegex(ValueError, "--rx-threads = 3 must be at most 2"):
            parse(["--rx-threads", "3", "--payload", self.payload])
        with mock.patch("os.cpu_count", return_value=1):
            with self.assertRaisesRegex(ValueError, "--rx-threads = 2 must be at most the 1 CPU "
                                                    "cores of this machine"):
                parse(["--rx-threads", "2", "--payload", self.payload])


if __name__ == "__main__":
    gr_unittest.run(qa_isac)
