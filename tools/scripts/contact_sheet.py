#!/usr/bin/env python3
"""Contact sheet of model files: each OBJ/glTF rendered by fovref, one captioned tile per file.

    tools/scripts/contact_sheet.py OUT.png MODEL... [--fovref BIN] [--mode basic] [--size 256x192]
                           [--columns 4] [--views front,three-quarter] [--json OUT.json]
                           [--strict-obj]

Each model is rendered with `fovref render --scene MODEL` and `fovref scene info --json MODEL`
gives its caption: file name, triangles, warnings. Views: "front" is the file's own camera, or
fovref's default (docs/model-files.md: from +Z, framing the bounding sphere; the default light at
the camera); "three-quarter" looks at the bounding sphere's centre from the direction (1, 0.75, 1)
at the default camera's distance (a --camera file; the default light moves with it), which shows
flat models seen edge-on from the front. A file fovref refuses gets a grey tile with the error message.
The tiles go into an SVG (PNG tiles embedded), which rsvg-convert (Debian: librsvg2-bin) turns
into OUT.png; the SVG is kept next to it. --json writes one row per model (status, triangles,
warnings, the error). Exit status: 0 when every model rendered, 1 when some were refused, 2 on a
usage error.
"""
import argparse
import base64
import html
import json
import os
import shutil
import subprocess
import sys
import tempfile


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def wrap(text, width):
    words, lines, line = text.split(), [], ""
    for w in words:
        if len(line) + len(w) + 1 > width and line:
            lines.append(line)
            line = w
        else:
            line = (line + " " + w).strip()
    if line:
        lines.append(line)
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("models", nargs="+")
    built = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "gcc-O2",
                         "fovref")
    parser.add_argument("--fovref", default=shutil.which("fovref") or os.path.normpath(built),
                        help="the fovref binary (default: fovref on PATH, else the release build "
                             "of this source tree)")
    parser.add_argument("--mode", default="basic")
    parser.add_argument("--size", default="256x192")
    parser.add_argument("--columns", type=int, default=4)
    parser.add_argument("--views", default="front",
                        help="comma-separated: front, three-quarter (one tile each)")
    parser.add_argument("--json", dest="json_out")
    parser.add_argument("--strict-obj", action="store_true")
    args = parser.parse_args()
    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        print(f"contact_sheet: --size must be WxH, got '{args.size}'", file=sys.stderr)
        return 2
    if not (16 <= width <= 4096 and 16 <= height <= 4096 and args.columns >= 1):
        print("contact_sheet: --size must be 16..4096 each and --columns at least 1", file=sys.stderr)
        return 2
    if not (os.path.isfile(args.fovref) and os.access(args.fovref, os.X_OK)):
        print(f"contact_sheet: no fovref binary at '{args.fovref}': give --fovref BIN, put fovref "
              "on PATH, or build it (bash tools/scripts/test.sh builds build/gcc-O2/fovref)",
              file=sys.stderr)
        return 2
    if not shutil.which("rsvg-convert"):
        print("contact_sheet: rsvg-convert not found (Debian: librsvg2-bin)", file=sys.stderr)
        return 2
    extra = ["--strict-obj"] if args.strict_obj else []
    views = args.views.split(",")
    for view in views:
        if view not in ("front", "three-quarter"):
            print(f"contact_sheet: unknown view '{view}' (front, three-quarter)", file=sys.stderr)
            return 2
    rows = []
    with tempfile.TemporaryDirectory(prefix="fovref-contact-") as tmp:
        for k, model in enumerate(args.models):
            row = {"model": model, "name": os.path.basename(model)}
            print(f"[{k + 1}/{len(args.models)}] {model}", file=sys.stderr)
            info = run([args.fovref, "scene", "info", "--json", model] + extra)
            if info.returncode != 0:
                row.update(status="refused", error=(info.stderr or info.stdout).strip())
                rows.append(row)
                continue
            scene = json.loads(info.stdout)
            row.update(triangles=scene["triangles"], warnings=len(scene["warnings"]),
                       defaulted=scene.get("defaulted", []),
                       unsupported=len(scene.get("unsupported", [])), pngs=[])
            lo, hi = scene["bounds"]["min"], scene["bounds"]["max"]
            centre = [(a + b) / 2 for a, b in zip(lo, hi)]
            radius = sum((b - a) ** 2 for a, b in zip(lo, hi)) ** 0.5 / 2 or 0.5
            for v, view in enumerate(views):
                out = os.path.join(tmp, f"{k}-{v}")
                camera = []
                if view == "three-quarter":
                    norm = (1 + 0.75 ** 2 + 1) ** 0.5
                    eye = [c + 2 * radius * d / norm for c, d in zip(centre, (1, 0.75, 1))]
                    camera_file = out + "-camera.json"
                    with open(camera_file, "w") as f:
                        json.dump({"position": eye, "look_at": centre, "vfov_deg": 60}, f)
                    camera = ["--camera", camera_file]
                render = run([args.fovref, "-q", "render", "--scene", model, "--mode", args.mode,
                              "--width", str(width), "--height", str(height), "--out", out] +
                             extra + camera)
                if render.returncode != 0:
                    row.update(status="refused", error=(render.stderr or render.stdout).strip())
                    break
                with open(os.path.join(out, "f000_final.png"), "rb") as f:
                    row["pngs"].append(base64.b64encode(f.read()).decode())
            else:
                row["status"] = "rendered"
            rows.append(row)

    caption = 34
    tile_w = len(views) * width + (len(views) - 1) * 2
    columns = max(1, min(args.columns // len(views) if len(views) > 1 else args.columns, len(rows)))
    lines_of = (len(rows) + columns - 1) // columns
    svg_w, svg_h = columns * (tile_w + 8) + 8, lines_of * (height + caption + 8) + 8
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
             f'width="{svg_w}" height="{svg_h}" font-family="DejaVu Sans, sans-serif">',
             f'<rect width="{svg_w}" height="{svg_h}" fill="#ffffff"/>']
    for k, row in enumerate(rows):
        x, y = 8 + (k % columns) * (tile_w + 8), 8 + (k // columns) * (height + caption + 8)
        name = html.escape(row["name"])
        if row["status"] == "rendered":
            for v, png in enumerate(row["pngs"]):
                parts.append(f'<image x="{x + v * (width + 2)}" y="{y}" width="{width}" '
                             f'height="{height}" xlink:href="data:image/png;base64,{png}"/>')
            detail = f'{row["triangles"]} triangles, {row["warnings"]} warnings'
            if row["unsupported"]:
                detail += f', {row["unsupported"]} unsupported'
        else:
            parts.append(f'<rect x="{x}" y="{y}" width="{tile_w}" height="{height}" '
                         f'fill="#9a9a9a"/>')
            for i, line in enumerate(wrap(row["error"].replace("fovref: ", ""), tile_w // 7)[:9]):
                parts.append(f'<text x="{x + 6}" y="{y + 18 + 14 * i}" font-size="11" '
                             f'fill="#ffffff">{html.escape(line)}</text>')
            detail = "refused"
        parts.append(f'<text x="{x}" y="{y + height + 14}" font-size="12" font-weight="bold">'
                     f'{name}</text>')
        parts.append(f'<text x="{x}" y="{y + height + 28}" font-size="11" fill="#444444">'
                     f'{html.escape(detail)}</text>')
    parts.append("</svg>")
    svg_path = os.path.splitext(args.out)[0] + ".svg"
    with open(svg_path, "w") as f:
        f.write("\n".join(parts))
    convert = run(["rsvg-convert", "-o", args.out, svg_path])
    if convert.returncode != 0:
        print(f"contact_sheet: rsvg-convert failed: {convert.stderr.strip()}", file=sys.stderr)
        return 2
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump([{k: v for k, v in r.items() if k != "pngs"} for r in rows], f, indent=1)
    rendered = sum(r["status"] == "rendered" for r in rows)
    print(f"contact_sheet: {rendered} of {len(rows)} rendered; wrote {args.out} and {svg_path}")
    return 0 if rendered == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())
