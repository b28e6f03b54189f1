#!/usr/bin/env python3
"""Per-pass times of the Vulkan compute port against the oracle's stages, measured in one run.

usage: pass_times.py FOVREF VK_PASSES [--size WxH] [--device lavapipe|any] [--json OUT] PASS:CASE...

For each PASS:CASE: `fovref golden export CASE --width W --height H --raw-copies --timings` (the
oracle's stage wall times per frame, single-threaded, in the manifest), then `vk_passes PASS` on
that bundle, the fastest of 3 runs (its port.json: the device time of the pass's dispatches,
submit to completion, without the upload and the pipeline's creation), and the diff's verdict with --profile vulkan.
The oracle's time of a pass is the sum over the frames of the stages whose buffers the pass
wrote. Prints a table (ms per frame) and, with --json, writes the rows. Default size 1280x720.
"""
import json
import os
import re
import subprocess
import sys
import tempfile


def run(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode not in (0, 1):
        sys.exit("pass_times: %s failed (%d): %s" % (" ".join(command), result.returncode,
                                                      result.stderr.strip()[-400:]))
    return result


def oracle_ms(bundle, dump):
    """The oracle's ms over all frames for the stages whose buffers the dump holds."""
    manifest = json.load(open(os.path.join(bundle, "manifest.json")))
    written = set()
    for name in os.listdir(dump):
        m = re.match(r"f(\d+)_(.+)\.(pfm|f32)$", name)
        if m:
            written.add((int(m.group(1)), m.group(2)))
    total, stages = 0.0, set()
    for frame in manifest["frames"]:
        names = {b["stage"] for b in frame["buffers"] if (frame["frame"], b["name"]) in written}
        for s in frame["stages"]:
            if s["name"] in names and "seconds" in s:
                total += s["seconds"]
                stages.add(s["name"])
    return 1000.0 * total, sorted(stages), len(manifest["frames"])


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        sys.exit(__doc__)
    fovref, client = args[0], args[1]
    size, device, out_json, pairs = "1280x720", "lavapipe", None, []
    k = 2
    while k < len(args):
        if args[k] in ("--size", "--device", "--json"):
            value = args[k + 1]
            if args[k] == "--size":
                size = value
            elif args[k] == "--device":
                device = value
            else:
                out_json = value
            k += 2
        else:
            pairs.append(args[k].split(":", 1))
            k += 1
    width, height = size.split("x")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for pass_name, case in pairs:
            bundle = os.path.join(tmp, "g_%s_%s%s" % (case, size, "_scene" if pass_name == "frame" else ""))
            if not os.path.isdir(bundle):
                scene = ["--with-scene"] if pass_name == "frame" else []
                run([fovref, "-q", "golden", "export", case, bundle, "--width", width, "--height",
                     height, "--raw-copies", "--timings"] + scene)
            dump = os.path.join(tmp, "v_%s_%s" % (pass_name, case))
            flags = ["--repeat=3"] + (["--lavapipe"] if device == "lavapipe" else [])
            run([client] + flags + [pass_name, bundle, dump])
            port = json.load(open(os.path.join(dump, "port.json")))
            fovref_ms, stages, frames = oracle_ms(bundle, dump)
            verdict = run([fovref, "diff", bundle, dump, "--profile", "vulkan", "-q"]).returncode
            rows.append({"pass": pass_name, "case": case, "size": size, "frames": frames,
                         "stages": stages, "fovref_ms_per_frame": fovref_ms / frames,
                         "device_ms_per_frame": port["device_ms"] / frames,
                         "ratio": (fovref_ms / port["device_ms"]) if port["device_ms"] > 0 else None,
                         "diff": "pass" if verdict == 0 else "FAIL", "device": port["device"]})
    print("%-24s %-36s %6s %12s %12s %8s %5s" % ("pass", "case", "frames", "fovref ms/f",
                                                  "device ms/f", "speedup", "diff"))
    for r in rows:
        print("%-24s %-36s %6d %12.2f %12.2f %8s %5s" % (
            r["pass"], r["case"], r["frames"], r["fovref_ms_per_frame"], r["device_ms_per_frame"],
            "%.2fx" % r["ratio"] if r["ratio"] else "-", r["diff"]))
    if rows:
        print("device: %s; size %s; fovref: the stages' single-threaded wall time" % (
            rows[0]["device"], size))
    if out_json:
        json.dump(rows, open(out_json, "w"), indent=1)


main()
