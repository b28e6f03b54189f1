# A real OpenGL client (tools/clients/gl_gbuffer.cpp: OpenGL 4.5 through EGL, Mesa's surfaceless
# platform, llvmpipe) renders
# the G-buffer of three procedural scenes with fovref's conventions; `fovref diff --profile
# gpu-raster --require ...` must pass on it, and fail, naming the right buffer and pixel, when one
# triangle's id or one depth is perturbed. Also: a misnamed file with --require, a background
# convention mismatch, and the HTML report checked in headless Chromium (plot axes, states).
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)
CLIENT=$(dirname "$FOVREF")/gl_gbuffer
if [ ! -x "$CLIENT" ]; then
  echo "FAIL: $CLIENT was not built: EGL or OpenGL is missing (apt-get install libegl-dev"
  echo "      libopengl-dev libegl-mesa0, which tools/scripts/setup.sh does), then reconfigure"
  exit 1
fi
REQUIRE=gbuffer_primitive_id,gbuffer_material_id,gbuffer_view_depth,gbuffer_hit_distance,gbuffer_world_position,gbuffer_shading_normal,gbuffer_geometric_normal,gbuffer_albedo
SIZE=(--width 320 --height 180)

# Three scenes: two golden cases, one case with its parameters overridden.
expect 0 "export cornell" -- "$FOVREF" golden export cornell-basic-raster "$TMP/g_cornell" "${SIZE[@]}" --param fill_rule=gl --with-scene -q
expect 0 "export checker-room" -- "$FOVREF" golden export checker-room-basic-raster "$TMP/g_checker" "${SIZE[@]}" --param fill_rule=gl --with-scene -q
expect 0 "export glossy-floor" -- "$FOVREF" golden export glossy-floor-basic "$TMP/g_glossy" "${SIZE[@]}" --param primary=raster --param fill_rule=gl --with-scene -q
for s in cornell checker glossy; do
  expect 0 "OpenGL renders $s" -- "$CLIENT" "$TMP/g_$s" "$TMP/o_$s"
  contains "llvmpipe" "$s rendered by llvmpipe"
  expect 0 "gpu-raster diff passes on $s" -- "$FOVREF" diff "$TMP/g_$s" "$TMP/o_$s" --profile gpu-raster --require "$REQUIRE"
  contains "RESULT: PASS (8 compared, 0 out of tolerance, 2 missing in the candidate)" "$s: all eight buffers compared"
  echo "$OUT" | grep -E "_id |view_depth "
done
expect 1 "the bit-exact default does not pass a GPU" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/o_cornell"

# Perturb the candidate: one interior primitive id, then one depth (PFM rows bottom to top).
"$PY" - "$TMP/g_cornell" "$TMP/o_cornell" "$TMP" <<'PYTHON'
import struct, sys, shutil
gold, cand, tmp = sys.argv[1:4]
def read(path):
    data = open(path, "rb").read()
    offset = 0
    for _ in range(3):
        offset = data.index(b"\n", offset) + 1
    w, h = map(int, data.split(b"\n")[1].split())
    return bytearray(data), offset, w, h
def get(f, x, y):
    data, offset, w, h = f
    at = offset + ((h - 1 - y) * w + x) * 4
    return struct.unpack("<f", data[at:at + 4])[0], at
ids = read(gold + "/f000_gbuffer_primitive_id.pfm")
w, h = ids[2], ids[3]
# The first pixel (row-major from the centre row) whose 3x3 neighbourhood shows one id.
def interior(y0):
    for y in range(y0, h - 1):
        for x in range(1, w - 1):
            v = get(ids, x, y)[0]
            if v >= 0 and all(get(ids, x + dx, y + dy)[0] == v for dx in (-1, 0, 1) for dy in (-1, 0, 1)):
                return x, y, v
x, y, v = interior(h // 2)
for name, change in (("id", lambda f, at: struct.pack("<f", v + 1.0)),
                     ("depth", lambda f, at: struct.pack("<f", struct.unpack("<f", f[0][at:at + 4])[0] * 1.01))):
    shutil.copytree(cand, f"{tmp}/p_{name}")
    path = f"{tmp}/p_{name}/f000_gbuffer_{'primitive_id' if name == 'id' else 'view_depth'}.pfm"
    f = read(path)
    _, at = get(f, x, y)
    f[0][at:at + 4] = change(f, at)
    open(path, "wb").write(f[0])
open(f"{tmp}/pixel.txt", "w").write(f"{x} {y}")
PYTHON
read -r PX PY_ < "$TMP/pixel.txt"
expect 1 "one interior primitive id changed" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/p_id" --profile gpu-raster --require "$REQUIRE" --html "$TMP/html_id" --json "$TMP/id.json"
contains "first failing stage: primary_visibility, buffer 'gbuffer_primitive_id', frame 0: 1 interior" "names the id buffer"
contains "interior mismatch ($PX, $PY_)" "names the pixel"
contains "explain it: fovref probe --scene cornell --mode basic --width 320 --height 180 --frame 0 --pixel $PX,$PY_" "probe command at that pixel"
contains "(1 px where ids differ left out)" "depth compared only where the ids agree"
expect 1 "one depth changed by 1%" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/p_depth" --profile gpu-raster --require "$REQUIRE" --html "$TMP/html_depth"
contains "first failing stage: primary_visibility, buffer 'gbuffer_view_depth', frame 0: 1 pixel(s) out of tolerance" "names the depth buffer"
contains "first failing pixel ($PX, $PY_)" "names the depth pixel"

# A misnamed file: not compared; --require makes it fail and the report suggests the name.
cp -r "$TMP/o_cornell" "$TMP/misnamed"
mv "$TMP/misnamed/f000_gbuffer_view_depth.pfm" "$TMP/misnamed/f000_gbuffer_view_depht.pfm"
expect 0 "a misnamed file without --require" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/misnamed" --profile gpu-raster
contains "did you mean f000_gbuffer_view_depth.pfm?" "suggests the buffer name"
contains "1 file ignored" "counts the ignored file"
expect 1 "a misnamed file with --require" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/misnamed" --profile gpu-raster --require "$REQUIRE"
contains "gbuffer_view_depth         MISSING" "the required buffer is MISSING"
contains "1 of them required" "counted as required"
expect 2 "--require of an unknown buffer" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/o_cornell" --require gbuffer_depth
contains "the golden has no buffer 'gbuffer_depth'" "unknown required buffer"
expect 2 "unknown profile" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/o_cornell" --profile gpu-fast
contains "unknown profile" "unknown profile"

# Background convention: a depth buffer cleared to +inf instead of 0.
cp -r "$TMP/o_cornell" "$TMP/inf"
"$PY" - "$TMP/inf/f000_gbuffer_view_depth.pfm" "$TMP/inf/f000_gbuffer_primitive_id.pfm" <<'PYTHON'
import struct, sys
depth, ids = (bytearray(open(p, "rb").read()) for p in sys.argv[1:3])
offset = sum(len(l) + 1 for l in bytes(depth).split(b"\n")[:3])
for at in range(offset, len(depth), 4):
    if struct.unpack("<f", ids[at:at + 4])[0] < 0:
        depth[at:at + 4] = struct.pack("<f", float("inf"))
open(sys.argv[1], "wb").write(depth)
PYTHON
expect 1 "depth cleared to +inf" -- "$FOVREF" diff "$TMP/g_cornell" "$TMP/inf" --profile gpu-raster --html "$TMP/html_inf"
contains "convention mismatch" "reported as a convention mismatch"
contains "fovref writes 0 depth" "says fovref's convention"

# The HTML reports in a real browser.
"$PY" - "$TMP/html_depth/index.html" "$TMP/id.json" <<'PYTHON' || { echo "FAIL: report content"; failures=$((failures + 1)); }
import json, re, sys
html = open(sys.argv[1]).read()
plots = re.findall(r"<svg .*?</svg>", html, re.S)
assert plots, "no plots"
for svg in plots:
    title = re.search(r'font-size="13">([^<]*)<', svg).group(1)
    ticks = re.findall(r'class="tick-y"[^>]*>([^<]*)<', svg)
    assert len(ticks) == len(set(ticks)), (title, ticks)  # distinct tick labels
    if title.startswith("RMSE"):
        assert all(float(t) >= 0 for t in ticks), (title, ticks)  # an error axis stays >= 0
assert 'class="status-missing">missing<' in html  # missing has its own style
report = json.load(open(sys.argv[2]))
depth = next(b for b in report["buffers"] if b["name"] == "gbuffer_view_depth")
assert depth["masked_pixels"] == 1 and depth["masked_by"] == ["gbuffer_primitive_id", "gbuffer_material_id"] or depth["masked_by"] == ["gbuffer_material_id", "gbuffer_primitive_id"], depth
ids = next(b for b in report["buffers"] if b["name"] == "gbuffer_primitive_id")
assert ids["compared_as"] == "ids" and ids["interior_mismatches"] == 1 and "psnr" not in ids
PYTHON
checks=$((checks + 1))
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -n "$CHROMIUM" ]; then
  for r in html_id html_depth html_inf; do
    expect 0 "Chromium renders $r" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --window-size=1400,1000 --dump-dom "file://$TMP/$r/index.html"
    checks=$((checks + 1))
    decoded=$(grep -o 'id="images-loaded">[0-9]* of [0-9]* decoded' <<<"$OUT")
    plots=$(grep -o 'id="plot-check">[^<]*' <<<"$OUT" | sed 's/.*>//')
    if [[ "$decoded" =~ \>([0-9]+)\ of\ ([0-9]+)\ decoded ]] && [ "${BASH_REMATCH[1]}" = "${BASH_REMATCH[2]}" ] &&
       [[ "$plots" =~ ,\ 0\ clipped,\ 0\ repeated\ ticks$ ]]; then
      echo "chromium $r: $decoded; $plots"
    else
      echo "FAIL: $r in Chromium: '$decoded', '$plots'"; failures=$((failures + 1))
    fi
  done
  expect 0 "Chromium: id report" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --dump-dom "file://$TMP/html_id/index.html"
  contains 'alt="id mismatches gbuffer_primitive_id"' "mismatch map with markers"
  contains '1 interior mismatches' "id counts in the report"
  expect 0 "Chromium: depth report" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --dump-dom "file://$TMP/html_depth/index.html"
  contains " plots, " "plots laid out"
else
  echo "SKIPPED: headless Chromium checks (chromium is not installed: apt-get install chromium)"
fi
finish
