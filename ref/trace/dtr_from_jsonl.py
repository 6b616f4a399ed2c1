#!/usr/bin/env python3
"""Independent writer of dynref trace schema 3 (ref/trace/README.md), in Python.

Converts a canonical JSONL dump (`dynref trace dump RUN --format jsonl`) -- or JSONL written by
any other implementation in that form -- into a binary trace.dtr that `dynref diff` reads.
It exists (1) as the reference for implementers in other languages and (2) to test that the
README alone is enough to write a trace dynref accepts (tests/trace: python round trip).

usage: dtr_from_jsonl.py RECORDS.jsonl OUT.dtr [--header HEADER.jsonl] [--level full|frames]
                         [--end-state complete] [--reverse-within-frame]
"""
import argparse
import json
import struct

def crc32c(data, crc=0):
    """CRC-32C (Castagnoli, reflected 0x82F63B78), bytewise; crc32c(b"123456789") == 0xE3069283."""
    c = crc ^ 0xFFFFFFFF
    for b in data:
        c = _CRC_TABLE[(c ^ b) & 0xFF] ^ (c >> 8)
    return c ^ 0xFFFFFFFF


def _crc_table():
    table = []
    for b in range(256):
        c = b
        for _ in range(8):
            c = (c >> 1) ^ 0x82F63B78 if c & 1 else c >> 1
        table.append(c)
    return table


_CRC_TABLE = _crc_table()

SCHEMA_VERSION = 3

KINDS = ["feature", "map_point", "keyframe", "line_sample", "plane", "instance_mask",
         "pixel_region", "frame"]


class Writer:
    def __init__(self):
        self.buf = bytearray()
        self.strings = {}
        self.table = []

    def u8(self, v): self.buf.append(v)
    def u32(self, v): self.buf += struct.pack("<I", v)
    def u64(self, v): self.buf += struct.pack("<Q", v)
    def f64(self, v): self.buf += struct.pack("<d", v)

    def varint(self, v):
        while v >= 0x80:
            self.buf.append((v & 0x7F) | 0x80)
            v >>= 7
        self.buf.append(v)

    def svarint(self, v): self.varint(((v << 1) ^ (v >> 63)) & 0xFFFFFFFFFFFFFFFF)

    def str(self, s):
        b = s.encode("utf-8")
        self.varint(len(b))
        self.buf += b

    def intern(self, s):  # STRING record, written before the record that uses it
        if s not in self.strings:
            self.strings[s] = len(self.table)
            self.table.append(s)
            self.u8(0x01)
            self.varint(self.strings[s])
            self.str(s)
        return self.strings[s]


def num(v):
    return float(v)  # JSON number, or the strings "nan" / "inf" / "-inf"


def write_record(w, r):
    t, f = r["type"], r["fields"]
    if t == "frame":
        w.u8(0x02); w.svarint(r["frame"]); w.f64(num(f["timestamp"]))
    elif t == "pose":
        i = w.intern(r["stage"])
        w.u8(0x03); w.varint(i)
        for k in range(12):
            w.f64(num(f["T_wc[%d]" % k]))
    elif t == "count":
        a, b = w.intern(r["stage"]), w.intern(r["entity"])
        w.u8(0x04); w.varint(a); w.varint(b); w.svarint(int(f["value"]))
    elif t == "obs":
        w.u8(0x05)
        w.svarint(int(r["entity"].split(".", 1)[1]))
        w.svarint(int(f["map_point_id"]))
        # schema 3; a schema 1/2 dump has none: the association is the final one there
        w.svarint(int(f.get("associated_map_point_id", f["map_point_id"])))
        w.f64(num(f["u"])); w.f64(num(f["v"])); w.f64(num(f["depth_m"]))
        w.svarint(int(f["octave"]))
        w.u64(int(f["descriptor_hash"], 16))
    elif t == "prob":
        inputs = [(k[3:], v) for k, v in f.items() if k.startswith("in.")]
        s = w.intern(r["stage"])
        ids = [w.intern(k) for k, _ in inputs]
        w.u8(0x06); w.varint(s); w.u8(KINDS.index(r["kind"])); w.str(r["entity"])
        w.varint(len(inputs))
        for i, (_, v) in zip(ids, inputs):
            w.varint(i); w.f64(num(v))
        w.f64(num(f["before"])); w.f64(num(f["after"]))
    elif t == "residual":
        c, k = w.intern(r["stage"]), w.intern(f["residual_kind"])
        start = [num(v) for key, v in f.items() if key.startswith("start[")]
        end = [num(v) for key, v in f.items() if key.startswith("end[")]
        w.u8(0x07); w.varint(c); w.varint(k); w.str(r["entity"])
        w.varint(len(start))
        for v in start: w.f64(v)
        w.varint(len(end))
        for v in end: w.f64(v)
        for key in ("information", "weight", "robust_loss", "chi2"):
            w.f64(num(f[key]))
        w.u8(1 if f["inlier"] == "1" else 0)
    elif t == "decision":
        s, reason = w.intern(r["stage"]), w.intern(f["reason"])
        w.u8(0x08); w.varint(s); w.u8(KINDS.index(r["kind"])); w.str(r["entity"])
        w.u8(1 if f["kept"] == "1" else 0); w.varint(reason)
    else:
        raise ValueError("unknown record type " + t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("records")
    ap.add_argument("out")
    ap.add_argument("--header")
    ap.add_argument("--level", default="full")
    ap.add_argument("--end-state", default="complete")
    ap.add_argument("--reverse-within-frame", action="store_true",
                    help="write each frame's non-FRAME records in reverse order (tests matching)")
    a = ap.parse_args()
    header = {}
    if a.header:
        with open(a.header) as fh:
            header = json.loads(fh.readline())
        for k in ("schema_version", "level", "end_state", "record_count", "frame_groups"):
            header.pop(k, None)
    groups = []  # [(frame, [records])] in order of first appearance
    with open(a.records) as fh:
        for line in fh:
            r = json.loads(line)
            if not groups or groups[-1][0] != r["frame"] or r["type"] == "frame":
                groups.append((r["frame"], []))
            groups[-1][1].append(r)
    w = Writer()
    w.buf += b"DYNTRACE" + struct.pack("<I", SCHEMA_VERSION) + bytes([["off", "frames", "full"].index(a.level), 0, 0, 0])
    w.varint(len(header))
    for k, v in header.items():
        w.str(k); w.str(v)
    w.u32(crc32c(w.buf))  # CRC-32C of preamble + header
    index, count = [], 0
    for frame, recs in groups:
        if a.reverse_within_frame:
            head = [r for r in recs if r["type"] == "frame"]
            recs = head + [r for r in reversed(recs) if r["type"] != "frame"]
        offset = len(w.buf)  # groups tile the body: a group starts with its first string
        for r in recs:
            if r["type"] != "frame":  # strings a record references come before it
                for s in pre_strings(r):
                    w.intern(s)
            write_record(w, r)
        index.append((frame, offset, len(recs)))
        count += len(recs)
    footer = len(w.buf)
    ends = [o for _, o, _ in index[1:]] + [footer]
    w.u8(0x7F); w.varint(count); w.str(a.end_state)
    w.varint(len(index))
    for (frame, offset, n), end in zip(index, ends):
        w.svarint(frame); w.varint(offset); w.varint(n)
        w.u32(crc32c(w.buf[offset:end]))  # CRC-32C of the group's bytes
    w.varint(len(w.table))
    for s in w.table:
        w.str(s)
    w.u32(crc32c(w.buf[footer:]))  # CRC-32C of the footer
    w.u64(footer)
    w.buf += b"DYNTREND"
    with open(a.out, "wb") as fh:
        fh.write(w.buf)


def pre_strings(r):
    """Strings a record references (interned before it starts)."""
    t, f = r["type"], r["fields"]
    if t == "pose": return [r["stage"]]
    if t == "count": return [r["stage"], r["entity"]]
    if t == "prob": return [r["stage"]] + [k[3:] for k in f if k.startswith("in.")]
    if t == "residual": return [r["stage"], f["residual_kind"]]
    if t == "decision": return [r["stage"], f["reason"]]
    return []


if __name__ == "__main__":
    main()
