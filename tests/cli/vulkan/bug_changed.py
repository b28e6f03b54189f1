"""bug_changed.py GOLDEN CORRECT BUGGY < diff output: the pixel the diff names as the first
failing one (in its buffer and frame) differs between the port's correct and buggy dumps, so the
diff points at a pixel the injected bug changed. Exit 0 when it does, 1 otherwise."""
import json
import os
import re
import struct
import sys


def pixel_value(directory, frame, name, width, height, channels, x, y):
    """The pixel's values in a dump: PFM rows bottom row first, raw .f32 top row first."""
    base = "%s/f%03d_%s" % (directory, frame, name)
    if os.path.exists(base + ".pfm"):
        data = open(base + ".pfm", "rb").read()
        header_end = 0
        for _ in range(3):
            header_end = data.index(b"\n", header_end) + 1
        data, row = data[header_end:], height - 1 - y
    else:
        data, row = open(base + ".f32", "rb").read(), y
    start = ((row * width + x) * channels) * 4
    return struct.unpack("<%df" % channels, data[start:start + channels * 4])


def main():
    golden, correct, buggy = sys.argv[1:4]
    text = sys.stdin.read()
    stage = re.search(r"first failing stage: (\S+), buffer '([^']+)', frame (\d+)", text)
    pixel = re.search(r"first failing pixel \((\d+), (\d+)\)", text)
    if not stage or not pixel:
        print("no first failing stage and pixel in the diff's output")
        return 1
    name, frame = stage.group(2), int(stage.group(3))
    x, y = int(pixel.group(1)), int(pixel.group(2))
    manifest = json.load(open(golden + "/manifest.json"))
    entry = [b for f in manifest["frames"] if f["frame"] == frame for b in f["buffers"] if b["name"] == name][0]
    size = (entry["width"], entry["height"], entry["channels"], x, y)
    if pixel_value(correct, frame, name, *size) == pixel_value(buggy, frame, name, *size):
        print("pixel (%d, %d) of %s, frame %d: the bug did not change it" % (x, y, name, frame))
        return 1
    return 0


sys.exit(main())
