#
# Copyright 2026 gr-nrsar authors.
#
# SPDX-License-Identifier: GPL-3.0-or-later
#
"""The UAV -> ground radio link of a split imaging chain (docs/scale.md): lines framed with a
sequence number and an HMAC, carried as bytes by gr-zeromq.

    UAV:    ... -> line_framer  ~~ bounded LineQueue ~~>  link_source -> zeromq push_sink
    ground: zeromq pull_source (bytes) -> line_deframer -> ... (the focuser)

gr-zeromq 3.10 exposes no CurveZMQ, and its sockets take messages from anyone who reaches
the port. What protects the link here: every line is one frame

    magic "NRSARLN1" | session u64 | seq u64 | flags u32 | bins u32 | tags_len u32
    | tags (TAG_BYTES, pmt-serialised dict) | line (bins complex64) | HMAC-SHA256 (32 bytes)

signed with a shared key (a key file of at least 32 bytes, readable by its owner only).
The ground verifies the HMAC before it reads anything else, so a stranger's frames, junk
bytes or replayed lines are rejected and counted, never focused; it is integrity and
authenticity, not secrecy (the lines travel in clear: use a tunnel, e.g. WireGuard, where
the imagery is confidential). The tags the focuser needs (range_axis, pulse_interval) are
inside the signed frame, which is why gr-zeromq's own pass_tags (unsigned, and a malformed
header throws in the source) is not used; the ground also reads the stream as bytes
(itemsize 1), since gr-zeromq throws on a message that is no whole number of vectors.

Faults. The UAV never blocks its radio path: line_framer always consumes its input and puts
frames into a LineQueue of fixed capacity; when the link cannot keep up (no ground, a dead
link) the newest lines are dropped and counted. link_source feeds the queue to push_sink in
its own thread, which waits for a peer as ZMQ PUSH does. The ground detects missing lines
from the sequence numbers and zero-fills them (the aperture keeps its length and timing;
a ground that joins late zero-fills the lines before its first one), reports what it lost,
and ends at the UAV's end frame, at the expected line count, or after an idle timeout.
Memory is bounded on both sides: the queue's capacity, the ZMQ high-water marks, the
deframer's buffer of at most a few frames; zero runs are counted, not stored.
"""

import collections
import hashlib
import hmac
import os
import secrets
import stat
import struct
import threading
import time

import numpy as np
import pmt
from gnuradio import gr

MAGIC = b"NRSARLN1"
HEADER = struct.Struct("<8sQQIII")
TAG_BYTES = 192
MAC_BYTES = 32
FLAG_END = 1
KEY_MIN_BYTES = 32
# tags that describe the stream from here on: every frame carries their last value, so a
# ground that joins late still has the axes
STICKY_TAGS = ("range_axis", "pulse_interval")
MAX_GAPS_REPORTED = 16
BUFFER_FRAMES = 64


def frame_bytes(bins):
    """Length of one frame carrying a line of `bins` complex64 values."""
    return HEADER.size + TAG_BYTES + 8 * bins + MAC_BYTES


def new_key():
    return secrets.token_bytes(KEY_MIN_BYTES)


def write_key(path):
    """A new random key in a file only its owner may read (mode 0600)."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(new_key())
    return path


def read_key(path, flag="--split-key"):
    """The shared key of a key file: at least KEY_MIN_BYTES bytes, not readable by group or
    others (ValueError naming the flag otherwise)."""
    try:
        st = os.stat(path)
        with open(path, "rb") as f:
            key = f.read()
    except OSError as err:
        raise ValueError(f"{flag} = {path!r} cannot be read: {err.strerror}") from None
    if st.st_mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise ValueError(f"{flag} = {path!r} has mode {stat.S_IMODE(st.st_mode):o}: a key "
                         f"file must be readable by its owner only (chmod 600)")
    if len(key) < KEY_MIN_BYTES:
        raise ValueError(f"{flag} = {path!r} holds {len(key)} bytes, fewer than "
                         f"{KEY_MIN_BYTES}")
    return key


def encode_frame(key, session, seq, line, tags, flags=0):
    """One signed frame (module doc); tags: {name: pmt value}."""
    blob = pmt.serialize_str(_tag_dict(tags)) if tags else b""
    if len(blob) > TAG_BYTES:
        raise ValueError(f"the tags of line {seq} need {len(blob)} bytes, more than "
                         f"{TAG_BYTES}")
    body = b"".join((HEADER.pack(MAGIC, session, seq, flags, line.size, len(blob)),
                     blob.ljust(TAG_BYTES, b"\0"),
                     np.ascontiguousarray(line, np.complex64).tobytes()))
    return body + hmac.new(key, body, hashlib.sha256).digest()


def _tag_dict(tags):
    d = pmt.make_dict()
    for name, value in tags.items():
        d = pmt.dict_add(d, pmt.intern(name), value)
    return d


def decode_frame(key, frame, bins):
    """(session, seq, flags, line, tags) of a frame whose HMAC and fields check, else None."""
    body, mac = frame[:-MAC_BYTES], frame[-MAC_BYTES:]
    if not hmac.compare_digest(hmac.new(key, body, hashlib.sha256).digest(), mac):
        return None
    magic, session, seq, flags, nbins, tags_len = HEADER.unpack_from(body)
    if nbins != bins or tags_len > TAG_BYTES:
        return None
    tags = {}
    if tags_len:
        d = pmt.deserialize_str(bytes(body[HEADER.size:HEADER.size + tags_len]))
        items = pmt.dict_items(d)
        for i in range(pmt.length(items)):
            pair = pmt.nth(i, items)
            tags[pmt.symbol_to_string(pmt.car(pair))] = pmt.cdr(pair)
    line = np.frombuffer(body, np.complex64, bins, HEADER.size + TAG_BYTES)
    return session, seq, flags, line, tags


class LineQueue:
    """The bounded hand-over between the UAV's radio path and its link: a full queue drops
    the line and counts it (after waiting at most `wait_s`: 0 for a radio, whose clock does
    not wait), get() waits at most `timeout`."""

    def __init__(self, capacity):
        self.capacity = capacity
        self._frames = collections.deque()
        self._cond = threading.Condition()
        self._closed = False
        self._stalled = False
        self.dropped = 0
        self.peak = 0

    def put(self, frame, force=False, wait_s=0.0):
        with self._cond:
            if wait_s > 0 and not force and not self._stalled:
                # one wait in vain marks the link stalled: no more waiting until it drains
                self._stalled = not self._cond.wait_for(
                    lambda: len(self._frames) < self.capacity, wait_s)
            if len(self._frames) >= self.capacity and not force:
                self.dropped += 1
                return False
            self._frames.append(frame)
            self.peak = max(self.peak, len(self._frames))
            self._cond.notify()
            return True

    def close(self):
        with self._cond:
            self._closed = True
            self._cond.notify()

    def get(self, timeout):
        """The next frame, None when none came within timeout; raises EOFError when closed
        and empty."""
        with self._cond:
            if not self._frames and not self._closed:
                self._cond.wait(timeout)
            if self._frames:
                self._stalled = False
                self._cond.notify_all()  # room for a waiting put()
                return self._frames.popleft()
            if self._closed:
                raise EOFError
            return None

    def __len__(self):
        return len(self._frames)


class line_framer(gr.sync_block):
    """UAV side: signs every input line (a vector of `bins` complex64) into a frame and puts
    it into `queue` without ever waiting (wait_s > 0: a simulation without a radio clock
    waits up to wait_s for room, as one graph would). After `lines` lines (0: endless) it
    queues the end frame (flags FLAG_END, seq = lines) and closes the queue; so does the end of its input."""

    def __init__(self, bins, key, queue, lines=0, session=None, wait_s=0.0):
        gr.sync_block.__init__(self, "line_framer", [(np.complex64, bins)], [])
        self.bins, self.key, self.queue, self.lines = bins, key, queue, lines
        self.wait_s = wait_s
        # the session number: the UAV's start time, so a later run's frames are newer
        self.session = time.time_ns() if session is None else session
        self.sticky = {}
        self.framed = 0
        self.done = threading.Event()

    def work(self, input_items, output_items):
        x = input_items[0]
        base = self.nitems_read(0)
        n = len(x)
        if self.lines:
            n = min(n, self.lines - base)
        at = collections.defaultdict(dict)
        for tag in self.get_tags_in_window(0, 0, n):
            at[tag.offset - base][pmt.symbol_to_string(tag.key)] = tag.value
        for i in range(n):
            tags = at.get(i, {})
            self.sticky.update({k: v for k, v in tags.items() if k in STICKY_TAGS})
            self.queue.put(encode_frame(self.key, self.session, base + i, x[i],
                                        {**tags, **self.sticky}), wait_s=self.wait_s)
            self.framed += 1
        if self.lines and base + n >= self.lines:
            self.finish()
        return len(x)

    def stop(self):
        # GNU Radio calls stop() when this block's input has ended: the end of the stream
        self.finish()
        return True

    def finish(self):
        """Queues the end frame (seq = the lines framed) and closes the queue, once."""
        if not self.done.is_set():
            self.queue.put(encode_frame(self.key, self.session, self.framed,
                                        np.zeros(self.bins, np.complex64), {}, FLAG_END),
                           force=True)
            self.queue.close()
            self.done.set()


class link_source(gr.sync_block):
    """UAV side: the frames of a LineQueue as a stream of frame vectors (uint8) for
    zeromq push_sink / pub_sink; ends when the queue is closed and empty."""

    def __init__(self, bins, queue, wait_s=0.05):
        self.size = frame_bytes(bins)
        gr.sync_block.__init__(self, "link_source", [], [(np.uint8, self.size)])
        self.queue, self.wait_s = queue, wait_s
        self.sent = 0

    def work(self, input_items, output_items):
        out = output_items[0]
        n = 0
        try:
            while n < len(out):
                frame = self.queue.get(self.wait_s if n == 0 else 0.0)
                if frame is None:
                    break
                out[n] = np.frombuffer(frame, np.uint8)
                n += 1
        except EOFError:
            if n == 0:
                return -1  # WORK_DONE
        self.sent += n
        return n


class line_deframer(gr.basic_block):
    """Ground side: bytes from zeromq pull_source / sub_source -> verified lines (vectors of
    `bins` complex64), missing lines zero-filled, the frames' tags re-emitted (module doc).

    lines: lines of the flight (0: endless; the end frame or the idle timeout ends it).
    idle_s: with no valid frame for this long the stream ends, zero-filled to `lines`."""

    def __init__(self, bins, key, lines=0, idle_s=10.0):
        gr.basic_block.__init__(self, "line_deframer", [np.uint8], [(np.complex64, bins)])
        self.bins, self.key, self.lines, self.idle_s = bins, key, lines, idle_s
        self.size = frame_bytes(bins)
        self.buf = bytearray()
        self.pending = collections.deque()  # ("line", seq, line, tags) / ("zeros", count)
        self.next_seq = 0  # the next line index to output
        self.session = None
        self.emitted_sticky = {}
        self.first_tags = None
        self.end_seq = None
        self.last_frame_time = time.monotonic()
        self.stats = dict(lines_received=0, lines_lost=0, frames_rejected=0,
                          frames_replayed=0, frames_other_session=0, junk_bytes=0,
                          idle_timeout=False, end_frame=False, first_seq=None)
        self.gaps = []

    def forecast(self, noutput_items, ninputs):
        # no input needed: the block is called while idle too, to keep its timeout
        return [0] * ninputs

    def report(self):
        """What reached the focuser and what was lost or refused (a dict)."""
        return dict(self.stats, gaps=[list(g) for g in self.gaps],
                    lines_out=int(self.nitems_written(0)))

    def _lose(self, first, count):
        if count > 0:
            self.pending.append(("zeros", count))
            self.stats["lines_lost"] += count
            if len(self.gaps) < MAX_GAPS_REPORTED:
                self.gaps.append((first, count))

    def _accept(self, frame):
        decoded = decode_frame(self.key, frame, self.bins)
        if decoded is None:
            self.stats["frames_rejected"] += 1
            return
        session, seq, flags, line, tags = decoded
        if self.session is None:
            self.session = session
        elif session != self.session:
            self.stats["frames_other_session"] += 1
            return
        if seq < self.next_seq:
            self.stats["frames_replayed"] += 1
            return
        self.last_frame_time = time.monotonic()
        if self.stats["first_seq"] is None:
            self.stats["first_seq"] = seq
            self.first_tags = {k: v for k, v in tags.items() if k in STICKY_TAGS}
        last = seq if self.lines == 0 else min(seq, self.lines)
        self._lose(self.next_seq, last - self.next_seq)
        self.next_seq = last
        if flags & FLAG_END:
            self.stats["end_frame"] = True
            self.end_seq = seq
            return
        if self.lines and seq >= self.lines:
            return
        self.pending.append(("line", seq, line.copy(), tags))
        self.stats["lines_received"] += 1
        self.next_seq = seq + 1

    def _parse(self):
        """Takes whole frames out of the byte buffer (resynchronising on the magic)."""
        while len(self.buf) >= self.size and self.end_seq is None:
            at = self.buf.find(MAGIC)
            if at < 0:
                keep = len(MAGIC) - 1
                self.stats["junk_bytes"] += len(self.buf) - keep
                del self.buf[:len(self.buf) - keep]
                return
            if at:
                self.stats["junk_bytes"] += at
                del self.buf[:at]
            if len(self.buf) < self.size:
                return
            before = self.stats["frames_rejected"]
            self._accept(bytes(self.buf[:self.size]))
            # a rejected frame may hide a real one after its magic: skip the magic only
            del self.buf[:len(MAGIC) if self.stats["frames_rejected"] > before else self.size]

    def _finishing(self):
        if self.end_seq is not None:
            return True
        if self.lines and self.next_seq >= self.lines:
            return True
        if time.monotonic() - self.last_frame_time > self.idle_s:
            self.stats["idle_timeout"] = True
            return True
        return False

    def general_work(self, input_items, output_items):
        inp, out = input_items[0], output_items[0]
        # at most BUFFER_FRAMES frames buffered: the rest waits upstream (bounded memory)
        take = min(len(inp), max(0, BUFFER_FRAMES * self.size - len(self.buf)))
        if take:
            self.buf += inp[:take].tobytes()
            self.consume(0, take)
        if not self.pending:
            self._parse()
        if not self.pending and self._finishing():
            if self.lines and self.next_seq < self.lines:
                self._lose(self.next_seq, self.lines - self.next_seq)
                self.next_seq = self.lines
            if not self.pending:
                return -1  # WORK_DONE
        n = 0
        base = self.nitems_written(0)
        if base == 0 and self.pending and self.first_tags is not None:
            # the stream's axes on its first line, even when that line is zero-filled
            for name, value in self.first_tags.items():
                self.add_item_tag(0, 0, pmt.intern(name), value)
            self.emitted_sticky.update(self.first_tags)
            self.first_tags = None
        while n < len(out) and self.pending:
            item = self.pending[0]
            if item[0] == "zeros":
                k = min(item[1], len(out) - n)
                out[n:n + k] = 0
                if item[1] > k:
                    self.pending[0] = ("zeros", item[1] - k)
                else:
                    self.pending.popleft()
                n += k
                continue
            _, seq, line, tags = self.pending.popleft()
            out[n] = line
            for name, value in tags.items():
                if name in STICKY_TAGS:
                    if pmt.equal(self.emitted_sticky.get(name, pmt.PMT_NIL), value):
                        continue
                    self.emitted_sticky[name] = value
                self.add_item_tag(0, base + n, pmt.intern(name), value)
            n += 1
        if n == 0 and not take:
            time.sleep(0.01)  # idle: nothing came (the scheduler calls again)
        return n


class uav_link(gr.hier_block2):
    """UAV side in one block (GRC: nrsar_uav_link): lines in -> line_framer, and
    link_source -> zeromq push_sink / pub_sink bound to `address`. key: the key bytes or a
    key file's path. wait_s: line_framer's (0, never wait, for a radio). Attributes framer,
    queue, source, sink."""

    def __init__(self, bins, key, address="tcp://127.0.0.1:5757", pattern="push", lines=0,
                 queue_lines=1024, hwm=16, wait_s=0.0):
        gr.hier_block2.__init__(self, "uav_link",
                                gr.io_signature(1, 1, gr.sizeof_gr_complex * bins),
                                gr.io_signature(0, 0, 0))
        from gnuradio import zeromq
        key = key if isinstance(key, bytes) else read_key(key, "key")
        self.queue = LineQueue(queue_lines)
        self.framer = line_framer(bins, key, self.queue, lines, wait_s=wait_s)
        self.source = link_source(bins, self.queue)
        make = {"push": zeromq.push_sink, "pub": zeromq.pub_sink}[pattern]
        self.sink = make(1, frame_bytes(bins), address, 100, False, hwm)
        self.connect(self, self.framer)
        self.connect(self.source, self.sink)

    def address(self):
        """The bound endpoint (the port chosen for a `:*` address)."""
        return self.sink.last_endpoint()

    def report(self):
        return {"lines": self.framer.lines, "lines_framed": self.framer.framed,
                "lines_dropped": self.queue.dropped, "queue_peak": self.queue.peak,
                "queue_capacity": self.queue.capacity, "frames_sent": self.source.sent,
                "frames_unsent": len(self.queue)}


class ground_link(gr.hier_block2):
    """Ground side in one block (GRC: nrsar_ground_link): zeromq pull_source / sub_source
    connected to `address` -> line_deframer -> lines out. Attributes source, deframer."""

    def __init__(self, bins, key, address="tcp://127.0.0.1:5757", pattern="push", lines=0,
                 idle_s=10.0, hwm=16):
        gr.hier_block2.__init__(self, "ground_link", gr.io_signature(0, 0, 0),
                                gr.io_signature(1, 1, gr.sizeof_gr_complex * bins))
        from gnuradio import zeromq
        key = key if isinstance(key, bytes) else read_key(key, "key")
        make = {"push": zeromq.pull_source, "pub": zeromq.sub_source}[pattern]
        self.source = make(1, 1, address, 100, False, hwm)
        self.deframer = line_deframer(bins, key, lines, idle_s)
        self.connect(self.source, self.deframer, self)

    def report(self):
        return self.deframer.report()
