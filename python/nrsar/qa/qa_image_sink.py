#!/usr/bin/python3
#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""QA of image_sink: tagged focused-image streams written to files; numpy.load must give
the exact image back, the PNG is decoded here with zlib and struct and its levels checked
against a float64 dB computation, the message port names the files, the ring deletes old
ones, a partial aperture is flushed at the end of the stream."""

import os
import shutil
import struct
import tempfile
import time
import zlib

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

try:
    from gnuradio import nrsar
except ImportError:
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bindings"))
    from gnuradio import nrsar


def read_png(path):
    """Minimal PNG reader (8-bit grey / RGB, filter 0): (h, w[, 3]) uint8 array."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, hdr = 8, b"", None
    while True:
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        ctype = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert crc == zlib.crc32(ctype + body) & 0xFFFFFFFF, ctype
        if ctype == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif ctype == b"IDAT":
            idat += body
        elif ctype == b"IEND":
            break
        pos += 12 + length
    w, h, depth, color = hdr[:4]
    assert depth == 8 and color in (0, 2)
    ch = 1 if color == 0 else 3
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * ch)
    assert (raw[:, 0] == 0).all()
    px = raw[:, 1:]
    return px.reshape(h, w) if ch == 1 else px.reshape(h, w, 3)


def levels(img, dr):
    """8-bit levels of 20 log10(|x| / max|x|) over [-dr, 0] dB, in float64."""
    a = np.abs(img.astype(np.complex128))
    with np.errstate(divide="ignore"):
        db = 20 * np.log10(a / a.max())
    return np.round(np.clip(255 * (db + dr) / dr, 0, 255)).astype(int)


def aperture_tags(index, first_item, lines, k, y0=10.0, dy=0.5):
    """The tags rd_focuser puts on the first line of an aperture."""
    def tag(key, value):
        return gr.tag_utils.python_to_tag((first_item, pmt.intern(key), value, pmt.intern("qa")))
    return [tag(nrsar.tag_keys.aperture, pmt.from_uint64(index)),
            tag(nrsar.tag_keys.azimuth_axis, pmt.make_tuple(pmt.from_double(y0), pmt.from_double(dy),
                                                            pmt.from_uint64(lines))),
            tag(nrsar.tag_keys.range_axis, pmt.make_tuple(pmt.from_double(900.0), pmt.from_double(1.5),
                                                          pmt.from_uint64(k)))]


class qa_image_sink(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()
        self.dir = tempfile.mkdtemp(prefix="nrsar_qa_image_sink_")
        self.rng = np.random.default_rng(7)

    def tearDown(self):
        self.tb = None
        shutil.rmtree(self.dir, ignore_errors=True)

    def image(self, m, k):
        x = (self.rng.standard_normal((m, k)) + 1j * self.rng.standard_normal((m, k))).astype(np.complex64)
        x[m // 3, k // 2] = 200 + 50j  # a bright target
        return x

    def run_sink(self, data, k, tags=(), **kw):
        src = blocks.vector_source_c(data.reshape(-1).tolist(), False, k, list(tags))
        sink = nrsar.image_sink(k, os.path.join(self.dir, "img"), **kw)
        dbg = blocks.message_debug()
        self.tb.connect(src, sink)
        self.tb.msg_connect(sink, "files", dbg, "store")
        self.tb.run()
        msgs = [pmt.to_python(dbg.get_message(i)) for i in range(dbg.num_messages())]
        return sink, msgs

    def test_npy_exact_and_png_levels(self):
        m, k = 24, 17
        imgs = [self.image(m, k) for _ in range(3)]
        tags = []
        for i in range(3):
            tags += aperture_tags(5 + i, i * m, m, k, y0=10.0 + i * m * 0.5)
        sink, msgs = self.run_sink(np.concatenate(imgs), k, tags, colormap=nrsar.image_colormap.GREY,
                                   dynamic_range_db=35.0)
        self.assertEqual(sink.apertures_written(), 3)
        for i, img in enumerate(imgs):
            n = 5 + i
            back = np.load(os.path.join(self.dir, f"img_{n}.npy"))
            self.assertEqual(back.dtype, np.complex64)
            self.assertEqual(back.shape, (m, k))
            np.testing.assert_array_equal(back, img)
            px = read_png(os.path.join(self.dir, f"img_{n}.png")).astype(int)
            ref = levels(img, 35.0)
            self.assertLessEqual(np.abs(px - ref).max(), 1)
            self.assertGreater((px == ref).mean(), 0.99)
            self.assertEqual(px[m // 3, k // 2], 255)
        # The message port: one dict per aperture naming the files and the axes.
        self.assertEqual(len(msgs), 3)
        self.assertEqual(msgs[1]["aperture"], 6)
        self.assertEqual(msgs[1]["npy"], os.path.join(self.dir, "img_6.npy"))
        self.assertEqual(msgs[1]["png"], os.path.join(self.dir, "img_6.png"))
        self.assertEqual(msgs[1]["lines"], m)
        self.assertFalse(msgs[1]["partial"])
        self.assertAlmostEqual(msgs[1]["azimuth_axis"][0], 10.0 + m * 0.5)
        self.assertEqual(tuple(msgs[1]["range_axis"]), (900.0, 1.5, k))

    def test_viridis_matches_matplotlib(self):
        import matplotlib
        m, k = 16, 32
        img = self.image(m, k)
        self.run_sink(img, k, aperture_tags(0, 0, m, k), write_npy=False)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "img_0.npy")))
        px = read_png(os.path.join(self.dir, "img_0.png")).astype(int)
        ref = np.round(matplotlib.colormaps["viridis"](levels(img, 40.0) / 255.0)[..., :3] * 255)
        self.assertLessEqual(np.abs(px - ref).max(), 3)

    def test_ring_keeps_last(self):
        m, k = 4, 8
        data = np.concatenate([self.image(m, k) for _ in range(6)])
        sink, msgs = self.run_sink(data, k, keep=2, lines_per_aperture=m)
        self.assertEqual(sink.apertures_written(), 6)
        self.assertEqual(sorted(os.listdir(self.dir)),
                         ["img_4.npy", "img_4.png", "img_5.npy", "img_5.png"])
        self.assertEqual([d["aperture"] for d in msgs], list(range(6)))
        np.testing.assert_array_equal(np.load(os.path.join(self.dir, "img_5.npy")), data[5 * m:])

    def test_partial_aperture_flushed_at_end(self):
        m, k = 10, 6
        img = self.image(m, k)
        data = np.concatenate([img, img[:3]])
        sink, msgs = self.run_sink(data, k, aperture_tags(0, 0, m, k) + aperture_tags(1, m, m, k))
        self.assertEqual(sink.apertures_written(), 2)
        np.testing.assert_array_equal(np.load(os.path.join(self.dir, "img_1.npy")), img[:3])
        self.assertEqual(sink.last_files()[0], os.path.join(self.dir, "img_1.npy"))
        # The message of an aperture written by stop() races the end of message delivery:
        # checked when it arrived.
        self.assertIn(len(msgs), (1, 2))
        if len(msgs) == 2:
            self.assertTrue(msgs[1]["partial"])
            self.assertEqual(msgs[1]["lines"], 3)

    def test_early_aperture_tag_splits(self):
        # An aperture tag before M lines closes the previous image as it is.
        m, k = 10, 5
        img = self.image(m, k)
        tags = aperture_tags(0, 0, m, k) + aperture_tags(1, 4, m, k)
        sink, msgs = self.run_sink(np.concatenate([img[:4], img]), k, tags)
        np.testing.assert_array_equal(np.load(os.path.join(self.dir, "img_0.npy")), img[:4])
        np.testing.assert_array_equal(np.load(os.path.join(self.dir, "img_1.npy")), img)
        self.assertEqual([d["partial"] for d in msgs], [True, False])

    def test_nonfinite_zeroed(self):
        m, k = 6, 4
        img = self.image(m, k)
        bad = img.copy()
        bad[1, 2] = np.nan
        bad[4, 0] = np.inf
        sink, _ = self.run_sink(bad, k, aperture_tags(0, 0, m, k))
        self.assertEqual(sink.nonfinite_count(), 2)
        want = img.copy()
        want[1, 2] = want[4, 0] = 0
        np.testing.assert_array_equal(np.load(os.path.join(self.dir, "img_0.npy")), want)
        px = read_png(os.path.join(self.dir, "img_0.png"))
        self.assertEqual(px.shape, (m, k, 3))

    def test_setters(self):
        sink = nrsar.image_sink(4, os.path.join(self.dir, "x"))
        sink.set_dynamic_range_db(25.0)
        self.assertEqual(sink.dynamic_range_db(), 25.0)
        sink.set_colormap(nrsar.image_colormap.GREY)
        self.assertEqual(sink.colormap(), nrsar.image_colormap.GREY)
        with self.assertRaises(ValueError):
            sink.set_dynamic_range_db(-1.0)

    def test_png_bytes_helper(self):
        px = (np.arange(35, dtype=np.uint8).reshape(5, 7) * 7)
        path = os.path.join(self.dir, "h.png")
        with open(path, "wb") as f:
            f.write(nrsar.png_bytes(px))
        np.testing.assert_array_equal(read_png(path), px)

    def check_rule(self, fragment, **kw):
        args = dict(num_range_bins=8, prefix=os.path.join(self.dir, "p"))
        args.update(kw)
        with self.assertRaises(ValueError) as ctx:
            nrsar.image_sink(**args)
        self.assertIn(fragment, str(ctx.exception))

    def test_rule_empty_prefix(self):
        self.check_rule("prefix = ''", prefix="")

    def test_rule_missing_folder(self):
        self.check_rule("does not exist", prefix=os.path.join(self.dir, "no", "p"))

    def test_rule_folder_is_a_file(self):
        # a prefix under a regular file: no user, root included, can create files there
        path = os.path.join(self.dir, "file")
        open(path, "w").close()
        self.check_rule("is not a folder", prefix=os.path.join(path, "p"))

    def test_rule_unwritable_folder(self):
        # Write permission is the rule's subject, and root (CI) has it everywhere: as root
        # the check runs in a child that has dropped to the unprivileged uid/gid 65534.
        ro = os.path.join(self.dir, "ro")
        os.mkdir(ro)
        os.chmod(ro, 0o500)
        os.chmod(self.dir, 0o755)  # the child may look into the test's folder, not into ro
        if os.geteuid() != 0:
            self.check_rule("not writable", prefix=os.path.join(ro, "p"))
            return
        pid = os.fork()
        if pid == 0:  # child: no unittest machinery, the verdict is the exit status
            code = 3
            try:
                os.setgid(65534)
                os.setuid(65534)
                nrsar.image_sink(8, os.path.join(ro, "p"))
                code = 1
            except ValueError as e:
                code = 0 if "not writable" in str(e) else 2
            finally:
                os._exit(code)
        for _ in range(3000):  # a constructor call: 30 s is far more than it needs
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                break
            time.sleep(0.01)
        else:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
            self.fail("child did not finish")
        self.assertEqual(os.waitstatus_to_exitcode(status), 0,
                         "0: 'not writable'; 1: no error; 2: another message; 3: setuid failed")

    def test_rule_dynamic_range(self):
        self.check_rule("dynamic_range_db = 0", dynamic_range_db=0.0)
        self.check_rule("dynamic_range_db = -3", dynamic_range_db=-3.0)

    def test_rule_keep_zero(self):
        self.check_rule("keep = 0", keep=0)

    def test_rule_no_format(self):
        self.check_rule("nothing to write", write_npy=False, write_png=False)

    def test_rule_zero_bins(self):
        self.check_rule("num_range_bins = 0", num_range_bins=0)


if __name__ == "__main__":
    gr_unittest.run(qa_image_sink)
