#!/usr/bin/env python3
"""Per-pass times of the Vulkan compute port against the oracle's stages, measured in one run.

usage: pass_times.py FOVREF VK_PASSES [--size WxH] [--device lavapipe|any] [--json OUT] PASS:CASE...

--size golden keeps each case's own size. For each PASS:CASE: `fovref golden export CASE --width W --height H --raw-copies --timings` (the
oracle's stage wall times per frame, single-threaded, in the manifest), then `vk_passes PASS` on
that bundle, the fastest of 3 runs (its port.json: the device time of the pass's dispatches,
submit to completion, without the upload and the pipeline's creation), and the diff's verdict with --profile vulkan:
the largest |error| (and its buffer), the near-threshold decision flips, the failing pixels
attributed to them, and the pixels beyond the per-element bounds (failing pixels and id
mismatches, which the profile's shares may still admit).
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


def decision_figures(report):
    """From the diff's JSON: the largest |error| over the compared value buffers, the buffer
    it is in, the near-threshold flips of the decision buffers and the pixels attributed."""
    worst, where, near, attributed, failing = 0.0, "-", 0, 0, 0
    for b in report["buffers"]:
        if b.get("max_abs_error") is not None and b["max_abs_error"] > worst:
            worst, where = b["max_abs_error"], b["name"]
        near += b.get("near_threshold_flips", 0)
        attributed += b.get("attributed_pixels", 0)
        failing += b.get("failing_pixels", 0) + b.get("edge_mismatches", 0) + \
            b.get("interior_mismatches", 0)
    return {"max_abs_error": worst, "max_error_buffer": where, "near_threshold_flips": near,
            "attributed_pixels": attributed, "pixels_beyond_bounds": failing}


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
    size_flags = [] if size == "golden" else ["--width", size.split("x")[0], "--height",
                                              size.split("x")[1]]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for pass_name, case in pairs:
            bundle = os.path.join(tmp, "g_%s_%s%s" % (case, size, "_scene" if pass_name == "frame" else ""))
            if not os.path.isdir(bundle):
                scene = ["--with-scene"] if pass_name == "frame" else []
                run([fovref, "-q", "golden", "export", case, bundle, "--raw-copies", "--timings"] +
                    size_flags + scene)
            dump = os.path.join(tmp, "v_%s_%s" % (pass_name, case))
            flags = ["--repeat=3"] + (["--lavapipe"] if device == "lavapipe" else [])
            run([client] + flags + [pass_name, bundle, dump])
            port = json.load(open(os.path.join(dump, "port.json")))
            fovref_ms, stages, frames = oracle_ms(bundle, dump)
            report = os.path.join(dump, "diff.json")
            verdict = run([fovref, "diff", bundle, dump, "--profile", "vulkan", "--json",
                           report]).returncode
            errors = decision_figures(json.load(open(report)))
            rows.append({"pass": pass_name, "case": case, "size": size, "frames": frames,
                         "stages": stages, "fovref_ms_per_frame": fovref_ms / frames,
                         "device_ms_per_frame": port["device_ms"] / frames,
                         "ratio": (fovref_ms / port["device_ms"]) if port["device_ms"] > 0 else None,
                         "diff": "pass" if verdict == 0 else "FAIL", "device": port["device"],
                         **errors})
    print("%-24s %-34s %3s %11s %11s %7s %5s %9s %-24s %4s %5s %5s" % (
        "pass", "case", "fr", "fovref ms/f", "device ms/f", "speedup", "diff", "max |err|",
        "in buffer", "near", "attr", "over"))
    for r in rows:
        print("%-24s %-34s %3d %11.2f %11.2f %7s %5s %9.3g %-24s %4d %5d %5d" % (
            r["pass"], r["case"], r["frames"], r["fovref_ms_per_frame"], r["device_ms_per_frame"],
            "%.2fx" % r["ratio"] if r["ratio"] else "-", r["diff"], r["max_abs_error"],
            r["max_error_buffer"], r["near_threshold_flips"], r["attributed_pixels"],
            r["pixels_beyond_bounds"]))
    if rows:
        print("device: %s; size %s; fovref: the stages' single-threaded wall time" % (
            rows[0]["device"], size))
    if out_json:
        json.dump(rows, open(out_json, "w"), indent=1)


main()
