# The diff report reads buffer space and says what the candidate file suggests (issue 29): a
# log-polar buffer gets errors along its columns and rows instead of eccentricity rings; a single
# wrong value is ringed in the heatmap; the console, the HTML and the JSON state the same counts;
# ignored files go into one line; a row-flipped PFM, a PNG for a float buffer and a PNG of an HDR
# buffer get a hint; --margin leaves a border band out and says how many pixels.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)
cd "$TMP" || exit 1
expect 0 "golden export" -- "$FOVREF" golden export cornell-cfov g -q
"$PY" "$SRC/tests/cli/fake_port.py" g c 0 --wrong lp_color:0:20:40:5 --wrong gaze_gbuffer_view_depth:0:5:5:9 || exit 1
cp g/*.png c/   # previews beside the buffers: ignored, in one line
expect 1 "one wrong lp_color texel, one wrong depth" -- "$FOVREF" diff g c --json r.json --html html
RESULT_LINE=$(grep '^RESULT' <<<"$OUT" | sed 's/^RESULT: FAIL (//; s/)$//')
contains "ignored: $(ls g/*.png | wc -l) files named like no golden buffer (f000_final.png, " "ignored files in one line"
checks=$((checks + 1))
if [ "$(grep -c '^ignored:' <<<"$OUT")" -ne 1 ]; then echo "FAIL: more than one 'ignored' line"; failures=$((failures + 1)); fi
"$PY" - "$RESULT_LINE" <<'PYEOF' || { echo "FAIL: the JSON report"; failures=$((failures + 1)); }
import json, sys
r = json.load(open("r.json"))
assert r["summary"] == sys.argv[1], (r["summary"], sys.argv[1])  # one count everywhere
assert r["out_of_tolerance"] == 2, r["out_of_tolerance"]
items = {(b["frame"], b["name"]): b for b in r["buffers"]}
lp = items[(0, "lp_color")]
assert "rings" not in lp and len(lp["column_rmse"]) == lp["width"] and len(lp["row_rmse"]) == lp["height"], lp.keys()
assert lp["column_rmse"][20] > 0 and lp["column_rmse"][19] == 0, lp["column_rmse"][18:22]
assert "rings" in items[(0, "final")] and "column_rmse" not in items[(0, "final")]
PYEOF
checks=$((checks + 1))
html=$(cat html/index.html)
grep -q "RMSE per column (along u)" <<<"$html" || { echo "FAIL: no column plot for lp_color"; failures=$((failures + 1)); }
checks=$((checks + 1))
grep -q "the 1 pixel out of tolerance ringed" <<<"$html" || { echo "FAIL: the outlier is not ringed"; failures=$((failures + 1)); }
checks=$((checks + 1))
grep -qF "RESULT: FAIL &mdash; $RESULT_LINE" <<<"$html" || { echo "FAIL: the HTML count differs from the console's ($RESULT_LINE)"; failures=$((failures + 1)); }

# A row-flipped PFM, a greyscale PNG for a depth buffer, a PNG of an HDR colour buffer
"$PY" - "$SRC/tests/cli" <<'PYEOF'
import struct, sys, zlib
sys.path.insert(0, sys.argv[1])
import fake_port
w, h, c, d = fake_port.read_pfm("g/f000_lp_gbuffer_view_depth.pfm")
rows = [d[r * w * c:(r + 1) * w * c] for r in range(h)]
fake_port.write_pfm("flipped.pfm", w, h, c, [v for r in reversed(rows) for v in r])
raw = b"".join(b"\0" + bytes(min(255, int(v * 40)) for v in rows[h - 1 - y]) for y in range(h))
chunk = lambda t, b: struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b))
open("depth.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) +
                              chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
PYEOF
expect 1 "a row-flipped PFM" -- "$FOVREF" diff g flipped.pfm --buffer lp_gbuffer_view_depth
contains "the candidate matches far better upside down (0 instead of" "the flip is named"
expect 1 "a greyscale PNG for a depth buffer" -- "$FOVREF" diff g depth.png --buffer lp_gbuffer_view_depth
contains "a PNG for a float buffer holds 8- or 16-bit steps" "the PNG is named"
expect 1 "a PNG of the HDR final image" -- "$FOVREF" diff g g/f000_final.png --buffer final
contains "the golden holds values above 1 (up to" "the clipping is named"
# --margin leaves the border band out and says how many pixels
"$PY" "$SRC/tests/cli/fake_port.py" g m 0 --wrong final:0:0:0:9 --wrong final:0:79:44:9 || exit 1
expect 1 "wrong corner pixels" -- "$FOVREF" diff g m
expect 0 "--margin 2" -- "$FOVREF" diff g m --margin 2 --json m.json
contains "px of the --margin band left out" "the band is counted"
"$PY" -c "
import json; r = json.load(open('m.json'))
f = [b for b in r['buffers'] if b['name'] == 'final'][0]
assert f['margin_pixels'] == 80 * 45 - 76 * 41, f['margin_pixels']" || { echo "FAIL: margin_pixels"; failures=$((failures + 1)); }
checks=$((checks + 1))
finish
