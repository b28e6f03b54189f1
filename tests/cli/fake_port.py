#!/usr/bin/env python3
"""A fake GPU port's dump of a golden bundle: every value buffer with a few ulps of noise.

usage: fake_port.py GOLDEN_DIR OUT_DIR ULPS [--wrong BUFFER:FRAME:X:Y:VALUE]...

Copies the bundle's PFM buffers to OUT_DIR (same file names): id buffers (kind "id") and buffers
of whole numbers (counts, ages, accept bits) unchanged, every other value moved by a deterministic pseudo-random -ULPS..ULPS ulps (0 stays 0). A
--wrong entry then sets every channel of one element (x, y in the image, row 0 at the top) of
one buffer of one frame to VALUE: one wrong texel in an intermediate stage. Non-PFM buffers
(EXR) are copied unchanged.
"""
import json
import os
import shutil
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = list(struct.unpack(("<" if scale < 0 else ">") + "f" * (width * height * channels),
                                  f.read(4 * width * height * channels)))
    return width, height, channels, data


def write_pfm(path, width, height, channels, data):
    with open(path, "wb") as f:
        f.write((b"PF\n" if channels == 3 else b"Pf\n") + f"{width} {height}\n-1.0\n".encode())
        f.write(struct.pack("<" + "f" * len(data), *data))


def nudge(value, ulps, seed):
    if value == 0.0 or value != value or ulps == 0:
        return value
    bits = struct.unpack("<i", struct.pack("<f", value))[0]
    step = (seed * 2654435761 >> 7) % (2 * ulps + 1) - ulps  # deterministic, -ulps .. ulps
    return struct.unpack("<f", struct.pack("<i", bits + step))[0]


def main():
    golden, out, ulps = sys.argv[1], sys.argv[2], int(sys.argv[3])
    wrong = [w.split(":") for k, w in enumerate(sys.argv) if k > 0 and sys.argv[k - 1] == "--wrong"]
    manifest = json.load(open(os.path.join(golden, "manifest.json")))
    os.makedirs(out, exist_ok=True)
    changed = 0
    for frame in manifest["frames"]:
        for b in frame["buffers"]:
            src = os.path.join(golden, b["file"]) if b.get("file") else None
            if not src or not os.path.exists(src):
                continue
            dst = os.path.join(out, os.path.basename(src))
            if not src.endswith(".pfm"):
                shutil.copyfile(src, dst)
                continue
            width, height, channels, data = read_pfm(src)
            # ids, and buffers of whole numbers (masks, counts, ages, accept bits) stay exact
            discrete = b.get("kind") == "id" or all(v == int(v) for v in data if v == v and abs(v) < 2**24)
            if not discrete:
                data = [nudge(v, ulps, k + 7919 * frame["frame"]) for k, v in enumerate(data)]
            for name, f, x, y, value in wrong:
                if name == b["name"] and int(f) == frame["frame"]:
                    if not (0 <= int(x) < width and 0 <= int(y) < height):
                        sys.exit(f"fake_port: ({x}, {y}) is outside {name}'s {width}x{height}")
                    row = height - 1 - int(y)  # PFM rows go bottom to top
                    for c in range(channels):
                        data[(row * width + int(x)) * channels + c] = float(value)
                    changed += 1
            write_pfm(dst, width, height, channels, data)
    if changed != len(wrong):
        sys.exit(f"fake_port: {len(wrong) - changed} --wrong buffer(s) not found")


if __name__ == "__main__":
    main()
