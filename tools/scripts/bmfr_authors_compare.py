#!/usr/bin/env python3
"""fovref's BMFR against the BMFR authors' OpenCL code, on one fovref-rendered sequence.

usage: bmfr_authors_compare.py --authors DIR [--fovref BIN] [--scene S] [--frames N]
                               [--size WxH] [--time-step DT] [--border B] [--hash jenkins|wang]
                               [--work DIR] [--json FILE]

DIR is a checkout of the authors' code (github.com/maZZZu/bmfr: opencl/bmfr.cpp, bmfr.cl,
CLUtils). Nothing of it is in this repository; the script builds a scratch copy under the work
directory and runs it on the OpenCL device 0 of platform 0 (PoCL on a machine without a GPU).

1. fovref renders N frames of the scene's camera path with `--mode pathtrace` (1 spp; pixel
   centres) and writes the radiance, albedo, shading normal and world position.
2. The input in the authors' conventions: colour = radiance / max(albedo, 0.01) in binary32
   (their data is demodulated), EXR files colorN.exr, albedoN.exr, shading_normalN.exr,
   world_positionN.exr, and camera_matrices.h: each frame's view-projection (computed from the
   manifest's camera as docs/bmfr.md states, in binary32), stored column-major as their kernel
   reads it (.s048c is row 0), with row 1 negated because their rows count upwards (their
   pixel y = (clip.y/w + 1)/2 H - (1 - offset.y), fovref's rows (1 - clip.y/w)/2 H - offset.y),
   pixel offsets (0.5, 0.5) and fovref's reprojection limits. The same numbers go to fovref
   as `denoise bmfr --demodulated` input (cameras.json with "view_projection", row-major).
3. The authors' code is built with these edits only: the image size, FRAME_COUNT and the input
   path, EXR output instead of 8-bit PNG (so differences below 1/255 are measurable), and two
   edits for OpenImageIO 2.4 (the namespace alias and ImageInput::open's unique_ptr), in C++17;
   with --fix-race also their read/write race at the border removed: accumulate_noisy_data
   reads the frame's colour from a copy taken before it runs (without it, a work item that
   gathers a mirrored border pixel may read the colour its owner already accumulated).
4. `fovref denoise bmfr --demodulated` with the authors' behaviour where fovref's default
   differs: bmfr_behind_camera=project, bmfr_sums=workgroup (the QR's sums in the order of
   their fitter kernel), bmfr_remodulate=albedo (no 0.01 floor when remodulating);
   --fovref-defaults keeps fovref's sums and remodulation. --hash sets bmfr_noise_hash and
   --storage bmfr_storage on both sides.
5. Per frame, the tone-mapped TAA output (theirs: outputN.exr; fovref: bmfr_taa): RMS and the
   largest difference over the interior (at least B pixels from every edge, default 32: one
   block) and over the border band.

Prerequisites (Debian 12): g++, pocl-opencl-icd, ocl-icd-opencl-dev, opencl-clhpp-headers,
libopenimageio-dev, openimageio-tools (oiiotool), libgl-dev, python3-numpy. docs/bmfr.md has
the measured figures.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np


def fail(message):
    sys.exit("bmfr_authors_compare: " + message)


def run(args, **kwargs):
    result = subprocess.run(args, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        fail("%s failed (exit %d):\n%s%s" % (" ".join(args), result.returncode,
                                             result.stdout[-3000:], result.stderr[-3000:]))
    return result.stdout


def read_pfm(path):
    """(rows top down, as an H x W x C float32 array)"""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, channels)[::-1].astype(np.float32)


def read_exr_uncompressed(path):
    """An uncompressed scanline float EXR (oiiotool -d float --compression none) as H x W x 3,
    rows top down; channels B, G, R are stored in name order."""
    data = open(path, "rb").read()
    offset, attributes = 8, {}
    while data[offset] != 0:
        name_end = data.index(b"\0", offset)
        type_end = data.index(b"\0", name_end + 1)
        size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
        attributes[data[offset:name_end]] = data[type_end + 5:type_end + 5 + size]
        offset = type_end + 5 + size
    offset += 1
    window = np.frombuffer(attributes[b"dataWindow"], dtype="<i4")
    width, height = int(window[2] - window[0] + 1), int(window[3] - window[1] + 1)
    if attributes[b"compression"] != b"\0":
        fail(path + ": expected an uncompressed EXR")
    offset += 8 * height  # the line offset table
    image = np.empty((height, width, 3), dtype=np.float32)
    for row in range(height):
        offset += 8  # y and the chunk's size
        line = np.frombuffer(data, dtype="<f4", count=3 * width, offset=offset)
        image[row] = line.reshape(3, width)[::-1].T  # B, G, R -> R, G, B
        offset += 12 * width
    return image


def write_pfm(path, image):
    height, width, channels = image.shape
    with open(path, "wb") as f:
        f.write((b"PF\n" if channels == 3 else b"Pf\n") + b"%d %d\n-1.0\n" % (width, height))
        f.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())


def view_projection(camera, width, height):
    """docs/bmfr.md "The view-projection matrix", in binary32, row-major."""
    f32 = np.float32
    c = [f32(v) for v in camera["position"]]
    t = f32(camera["tan_half_vfov"])
    rows = []
    for axis, scale in ((camera["right"], t * (f32(width) / f32(height))), (camera["up"], t),
                        (camera["forward"], f32(1)), (camera["forward"], f32(1))):
        a = [f32(v) for v in axis]
        translation = -((a[0] * c[0] + a[1] * c[1]) + a[2] * c[2])
        rows.append([v / scale for v in a + [translation]])
    return [float(v) for row in rows for v in row]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--authors", required=True, help="a checkout of github.com/maZZZu/bmfr")
    parser.add_argument("--fovref", default="build/gcc-O2/fovref")
    parser.add_argument("--scene", default="cornell")
    parser.add_argument("--frames", type=int, default=16)
    parser.add_argument("--size", default="1280x720")
    parser.add_argument("--time-step", default=None, help="seconds between frames (fovref's)")
    parser.add_argument("--border", type=int, default=32)
    parser.add_argument("--hash", default="jenkins", choices=["jenkins", "wang"])
    parser.add_argument("--storage", default="half", choices=["half", "float"],
                        help="the block matrix's storage on both sides (the authors' "
                             "USE_HALF_PRECISION_IN_TMP_DATA, fovref's bmfr_storage)")
    parser.add_argument("--fix-race", action="store_true",
                        help="remove the authors' read/write race at the border: "
                             "accumulate_noisy_data reads the frame's colour from a copy taken "
                             "before it runs")
    parser.add_argument("--fovref-defaults", action="store_true",
                        help="fovref's own bmfr_sums and bmfr_remodulate (binary64, floor) "
                             "instead of the authors' (workgroup, albedo)")
    parser.add_argument("--work", default="bmfr-authors-work")
    parser.add_argument("--json", default=None, help="also write the figures here")
    o = parser.parse_args()
    try:
        width, height = (int(v) for v in o.size.lower().split("x"))
    except ValueError:
        fail("--size: expected WxH, got '%s'" % o.size)
    if width < 64 or height < 64 or o.frames < 1 or o.border < 0:
        fail("--size must be at least 64x64, --frames at least 1, --border not negative")
    source = os.path.join(o.authors, "opencl")
    for name in ("bmfr.cpp", "bmfr.cl", "CLUtils/CLUtils.cpp", "CLUtils/CLUtils.hpp"):
        if not os.path.isfile(os.path.join(source, name)):
            fail("--authors %s: opencl/%s is missing (a checkout of maZZZu/bmfr?)" % (o.authors,
                                                                                     name))
    fovref = os.path.abspath(o.fovref)
    if not os.access(fovref, os.X_OK):
        fail("--fovref %s: not an executable" % o.fovref)
    if shutil.which("oiiotool") is None:
        fail("oiiotool is missing (apt-get install openimageio-tools)")
    work = os.path.abspath(o.work)
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)

    # 1. the sequence
    print("rendering %d frames of %s at %dx%d ..." % (o.frames, o.scene, width, height))
    inputs = ["radiance", "gbuffer_albedo", "gbuffer_shading_normal", "gbuffer_world_position"]
    render = [fovref, "-q", "render", "--scene", o.scene, "--mode", "pathtrace", "--param",
              "denoise=bmfr", "--width", str(width), "--height", str(height), "--frames",
              str(o.frames), "--out", os.path.join(work, "render"), "--output", ",".join(inputs)]
    if o.time_step:
        render += ["--time-step", o.time_step]
    run(render)
    manifest = json.load(open(os.path.join(work, "render", "manifest.json")))

    # 2. the input in the authors' conventions, for both
    ours, theirs = os.path.join(work, "input"), os.path.join(work, "authors-data")
    os.makedirs(ours)
    os.makedirs(theirs)
    authors_names = {"radiance": "color", "gbuffer_albedo": "albedo",
                     "gbuffer_shading_normal": "shading_normal",
                     "gbuffer_world_position": "world_position"}
    matrices = []
    for frame in range(o.frames):
        prefix = "f%03d_" % frame
        buffers = {b: read_pfm(os.path.join(work, "render", prefix + b + ".pfm")) for b in inputs}
        buffers["radiance"] = buffers["radiance"] / np.maximum(buffers["gbuffer_albedo"],
                                                               np.float32(0.01))
        for b in inputs:
            path = os.path.join(ours, prefix + b + ".pfm")
            write_pfm(path, buffers[b])
            run(["oiiotool", path, "-d", "float", "-o",
                 os.path.join(theirs, "%s%d.exr" % (authors_names[b], frame))])
        matrices.append(view_projection(manifest["frames"][frame]["camera"], width, height))
    limits = {"position_limit_squared": 0.01, "normal_limit_squared": 0.25}
    json.dump(dict(width=width, height=height, frames=[
        {"view_projection": m, "pixel_offset": [0.5, 0.5]} for m in matrices], **limits),
        open(os.path.join(ours, "cameras.json"), "w"))
    with open(os.path.join(theirs, "camera_matrices.h"), "w") as f:
        f.write("// written by fovref's tools/scripts/bmfr_authors_compare.py\n")
        for name, value in limits.items():
            f.write("const float %s = %.9ef;\n" % (name, value))
        f.write("const float camera_matrices[%d][4][4] = {\n" % o.frames)
        for m in matrices:
            columns = [[m[row * 4 + col] * (-1.0 if row == 1 else 1.0) for row in range(4)]
                       for col in range(4)]
            f.write("  {%s},\n" % ", ".join(
                "{%s}" % ", ".join("%.9ef" % v for v in c) for c in columns))
        f.write("};\nconst float pixel_offsets[%d][2] = {%s};\n" % (
            o.frames, ", ".join(["{0.5f, 0.5f}"] * o.frames)))

    # 3. the authors' code, built and run
    build = os.path.join(work, "authors-build")
    shutil.copytree(source, build)
    code = open(os.path.join(build, "bmfr.cpp")).read()
    edits = [
        ("#define IMAGE_WIDTH 1280", "#define IMAGE_WIDTH %d" % width),
        ("#define IMAGE_HEIGHT 720", "#define IMAGE_HEIGHT %d" % height),
        ("#define FRAME_COUNT 60", "#define FRAME_COUNT %d" % o.frames),
        ("#define INPUT_DATA_PATH ../data/frames", "#define INPUT_DATA_PATH " + theirs),
        ('std::to_string(frame) + ".png"', 'std::to_string(frame) + ".exr"'),
        ('#include "OpenImageIO/imageio.h"',
         '#include "OpenImageIO/imageio.h"\nnamespace OpenImageIO = OIIO;'),
        ("OpenImageIO::ImageInput *in = ", "auto in = "),
        ("#define USE_HALF_PRECISION_IN_TMP_DATA 1",
         "#define USE_HALF_PRECISION_IN_TMP_DATA %d" % (o.storage == "half")),
    ]
    for old, new in edits:
        if code.count(old) != 1:
            fail("the authors' bmfr.cpp is not the version this script knows: '%s'" % old)
        code = code.replace(old, new)
    if o.fix_race:
        for old, new in [
            ("        accum_noisy_kernel.setArg(arg_index++, sizeof(cl_int), &frame);\n",
             "        accum_noisy_kernel.setArg(arg_index++, sizeof(cl_int), &frame);\n"
             "        accum_noisy_kernel.setArg(arg_index++, noisy_copy);\n"
             "        queue.enqueueCopyBuffer(*noisy_buffer.current(), noisy_copy, 0, 0,\n"
             "            IMAGE_WIDTH * IMAGE_HEIGHT * 3 * sizeof(cl_float));\n"),
            ("    cl::Buffer accept_buffer(",
             "    cl::Buffer noisy_copy(context, CL_MEM_READ_WRITE, OUTPUT_SIZE * 3 * "
             "sizeof(cl_float));\n    cl::Buffer accept_buffer("),
        ]:
            if code.count(old) != 1:
                fail("the authors' bmfr.cpp is not the version this script knows: '%s'" % old)
            code = code.replace(old, new)
        kernel = open(os.path.join(build, "bmfr.cl")).read()
        for old, new in [
            ("      const float2 pixel_offset,\n      const int frame_number) {",
             "      const float2 pixel_offset,\n      const int frame_number,\n"
             "      const __global float* restrict noisy_copy) {"),
            ("   float3 current_color = load_float3(current_noisy, linear_pixel);",
             "   float3 current_color = load_float3(noisy_copy, linear_pixel);"),
        ]:
            if kernel.count(old) != 1:
                fail("the authors' bmfr.cl is not the version this script knows: '%s'" % old)
            kernel = kernel.replace(old, new)
        open(os.path.join(build, "bmfr.cl"), "w").write(kernel)
    open(os.path.join(build, "bmfr.cpp"), "w").write(code)
    print("building the authors' code ...")
    run(["g++", "-std=c++17", "-O2", "-DUNIX", "-o", "bmfr", "bmfr.cpp", "CLUtils/CLUtils.cpp",
         "-I.", "-lOpenCL", "-lOpenImageIO", "-lOpenImageIO_Util", "-lGL", "-fopenmp"], cwd=build)
    os.makedirs(os.path.join(build, "outputs"))
    print("running the authors' code ...")
    log = run(["./bmfr"], cwd=build)
    open(os.path.join(work, "authors.log"), "w").write(log)

    # 4. fovref on the same input
    print("running fovref denoise bmfr ...")
    params = ["bmfr_behind_camera=project", "bmfr_noise_hash=" + o.hash,
              "bmfr_storage=" + o.storage]
    if not o.fovref_defaults:
        params += ["bmfr_sums=workgroup", "bmfr_remodulate=albedo"]
    denoise = [fovref, "-q", "denoise", "bmfr", ours, os.path.join(work, "fovref"),
               "--demodulated", "--output", "bmfr_taa"]
    for p in params:
        denoise += ["--param", p]
    run(denoise)

    # 5. the comparison
    border = np.ones((height, width), dtype=bool)
    b = o.border
    border[b:height - b, b:width - b] = False
    rows = []
    print("frame  interior RMS  interior max   border RMS    border max   (%d px band)" % b)
    for frame in range(o.frames):
        exr = os.path.join(work, "authors-output%d.exr" % frame)
        run(["oiiotool", os.path.join(build, "outputs", "output%d.exr" % frame), "-d", "float",
             "--compression", "none", "-o", exr])
        a = read_exr_uncompressed(exr).astype(np.float64)
        f = read_pfm(os.path.join(work, "fovref", "f%03d_bmfr_taa.pfm" % frame)).astype(np.float64)
        d = f - a
        row = {"frame": frame}
        for name, mask in (("interior", ~border), ("border", border)):
            values = d[mask]
            row[name + "_rms"] = float(np.sqrt(np.mean(values * values))) if values.size else 0.0
            row[name + "_max"] = float(np.max(np.abs(values))) if values.size else 0.0
        rows.append(row)
        print("%5d  %12.3g  %12.3g  %11.3g  %12.3g" % (frame, row["interior_rms"],
                                                     row["interior_max"], row["border_rms"],
                                                     row["border_max"]))
    if o.json:
        json.dump({"scene": o.scene, "width": width, "height": height, "hash": o.hash, "storage": o.storage, "fix_race": o.fix_race, "fovref_params": params,
                   "border": b, "frames": rows}, open(o.json, "w"), indent=1)


if __name__ == "__main__":
    main()
