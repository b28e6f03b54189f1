# Hostile inputs and outputs through the CLI (issue "hardening"): each case used to crash, hit
# undefined behaviour, change its result from run to run, replace a device node, allocate before
# checking a size, or say something unclear; each must now exit 2 with one line naming the file,
# line, key or option (or succeed where the input is valid).
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

# --- JSON nested 100000 deep: refused before parsing, wherever JSON is read ---
mkdir -p "$TMP/deep" "$TMP/cases"
"$PY" -c "print('{\"a\":\n' + '['*100000 + ']'*100000 + '}')" > "$TMP/deep/manifest.json"
cp "$TMP/deep/manifest.json" "$TMP/cases/cases.json"
expect 2 "diff against a deep manifest" -- "$FOVREF" diff "$TMP/deep" "$TMP/deep"
contains "manifest.json:2: JSON nested deeper than 256" "diff: nesting"
expect 2 "golden list of a deep cases file" -- "$FOVREF" golden list --dir "$TMP/cases"
contains "cases.json:2: JSON nested deeper than 256" "golden list: nesting"
expect 2 "golden export into a directory with a deep manifest" -- "$FOVREF" golden export cornell-basic "$TMP/deep" -q
contains "not a fovref bundle" "the directory is left alone"
cp "$TMP/deep/manifest.json" "$TMP/tol.json"
expect 0 "a bundle to diff" -- "$FOVREF" golden export core-rng "$TMP/rng" -q
expect 2 "a deep tolerance file" -- "$FOVREF" diff "$TMP/rng" "$TMP/rng" --tolerance-file "$TMP/tol.json"
contains "tol.json:2: JSON nested deeper than 256" "tolerance file: nesting"

# --- A mistyped manifest member names the file, the line and the key ---
cp -r "$TMP/rng" "$TMP/typed"
"$PY" - "$TMP/typed/manifest.json" <<'PYTHON'
import sys
text = open(sys.argv[1]).read()
open(sys.argv[1], "w").write(text.replace('"name": "rng"', '"name": 17', 1))
PYTHON
expect 2 "a number where the manifest wants a string" -- "$FOVREF" diff "$TMP/typed" "$TMP/rng"
contains "malformed manifest: /frames/0/buffers/0/name: expected a string, got number" "key and type"
contains "manifest.json:" "file and line"

# --- The integer -0 in a scene (an UBSan abort) ---
mkdir -p "$TMP/scene"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$TMP/scene/tri.obj"
printf '{"version": 1, "meshes": [{"obj": "tri.obj"}],\n "camera": {"position": [0, -0, 5], "look_at": [0, 0, 0], "vfov_deg": 45}}\n' > "$TMP/scene/scene.json"
expect 0 "a scene with -0" -- "$FOVREF" scene info "$TMP/scene/scene.json"

# --- OBJ lines and points: tinyobjloader's own message replaced by file:line ---
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 0\nf 1 2 3\n' > "$TMP/scene/tri.obj"
expect 2 "an OBJ line with index 0" -- "$FOVREF" scene info "$TMP/scene/scene.json"
contains "tri.obj:4: vertex index 0 out of range" "OBJ file and line"

# --- A palette PNG whose indices exceed its palette (read undefined data: changed per run) ---
"$PY" - "$TMP/pal8.png" <<'PYTHON'
import struct, sys, zlib
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
raw = b"".join(b"\0" + bytes([1, 200, 0, 1]) for _ in range(4))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 3, 0, 0, 0))
png += chunk(b"PLTE", bytes([255, 0, 0, 0, 255, 0])) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
open(sys.argv[1], "wb").write(png)
PYTHON
expect 2 "diff of a palette PNG with indices beyond its palette" -- "$FOVREF" diff "$TMP/pal8.png" "$TMP/pal8.png"
contains "pal8.png: palette PNG: a pixel uses palette index 200 but the PLTE chunk has only 2 entries" "palette"

# --- Outputs: devices are written directly (never replaced), symlinks written through ---
expect 2 "--json /dev/full" -- "$FOVREF" diff "$TMP/rng" "$TMP/rng" --json /dev/full
contains "/dev/full: write error" "a failed write is reported"
checks=$((checks + 1))
[ -c /dev/full ] || { echo "FAIL: /dev/full is no longer a character device"; failures=$((failures + 1)); }
expect 0 "--json /dev/null" -- "$FOVREF" diff "$TMP/rng" "$TMP/rng" --json /dev/null
checks=$((checks + 1))
[ -c /dev/null ] || { echo "FAIL: /dev/null is no longer a character device"; failures=$((failures + 1)); }
ln -s report-target.json "$TMP/link.json"
expect 0 "--json through a symlink" -- "$FOVREF" diff "$TMP/rng" "$TMP/rng" --json "$TMP/link.json"
checks=$((checks + 1))
if [ -L "$TMP/link.json" ] && grep -q '"pass": true' "$TMP/report-target.json"; then :; else
  echo "FAIL: the symlink was replaced or its target not written"; failures=$((failures + 1))
fi

# --- Resource limits: sizes checked before allocating; unbounded inputs refused ---
head -c 288 /dev/zero > "$TMP/small.raw"
expect 2 "a 288-byte raw file said to be 16384x16384" -- timeout 20 "$FOVREF" diff "$TMP/rng" "$TMP/small.raw" --buffer rng --raw-size 16384x16384x1
contains "needs 1073741824 bytes, the file has 288" "size checked first"
expect 2 "a raw file said to be 65536x65536x64" -- "$FOVREF" diff "$TMP/rng" "$TMP/small.raw" --buffer rng --raw-size 65536x65536x64
contains "exceed the limit" "no bad_alloc"
expect 2 "/dev/zero as a tolerance file" -- timeout 20 "$FOVREF" diff "$TMP/rng" "$TMP/rng" --tolerance-file /dev/zero
contains "/dev/zero: is a device, not a file" "device refused"
expect 2 "/dev/zero as a ray file" -- timeout 20 "$FOVREF" rays trace cornell /dev/zero "$TMP/hits.bin"
contains "/dev/zero: is a device, not a file" "device refused"
expect 2 "a file over FOVREF_MAX_FILE_BYTES" -- env FOVREF_MAX_FILE_BYTES=100 "$FOVREF" diff "$TMP/rng/f000_rng.pfm" "$TMP/rng/f000_rng.pfm"
contains "exceed the limit of 100 (raise it with FOVREF_MAX_FILE_BYTES" "file size limit"
expect 2 "an image over FOVREF_MAX_IMAGE_PIXELS" -- env FOVREF_MAX_IMAGE_PIXELS=100 "$FOVREF" diff "$TMP/rng/f000_rng.pfm" "$TMP/rng/f000_rng.pfm"
contains "(raise it with FOVREF_MAX_IMAGE_PIXELS" "pixel limit"
expect 2 "a malformed limit variable" -- env FOVREF_MAX_RAYS=lots "$FOVREF" rays trace cornell "$TMP/small.raw" "$TMP/hits.bin"
contains "FOVREF_MAX_RAYS='lots': expected a positive integer" "variable named"

# --- Messages that name the option the user gave ---
expect 2 "probe --frame 100000" -- "$FOVREF" probe --scene cornell --mode basic --frame 100000 --pixel 1,1 --width 8 --height 8
contains "--frame 100000: must be in [0, 99999]" "the option given"
expect 2 "probe --width 0" -- "$FOVREF" probe --scene cornell --mode basic --width 0 --height 1 --pixel 1,1
contains "--width 0: must be in [1, 16384]" "the width, not the pixel"
expect 2 "--distance-px 1e9 --flip" -- "$FOVREF" diff "$TMP/rng" "$TMP/rng" --distance-px 1e9 --flip
contains "--distance-px 1e+09: with --flip" "refused when given"
printf '# no faces\n' > "$TMP/scene/tri.obj"
expect 2 "geometry of a scene without triangles" -- "$FOVREF" render --scene "$TMP/scene/scene.json" --mode geometry --width 1 --height 1 --out "$TMP/geo"
contains "has no triangles" "said in words"
checks=$((checks + 1))
[ ! -e "$TMP/geo" ] || { echo "FAIL: a half-written output directory was left"; failures=$((failures + 1)); }
finish
