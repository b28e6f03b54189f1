# Model files from the command line (docs/model-files.md, docs/obj-quirks.md): a bare OBJ is a
# scene for every command that takes one; quirks are warnings, --strict-obj errors; UTF-16 is a
# one-line error; --camera; the contact sheet; the installed tool finds its data anywhere.
source "$(dirname "$0")/lib.bash"
Q=$SRC/tests/scene/obj-quirks

# A bare OBJ: scene info says what was defaulted.
expect 0 "info of a bare OBJ" -- "$FOVREF" scene info "$Q/concave-polygon.obj"
contains "triangles  2" "info of a bare OBJ"
contains "defaulted  camera: at (2, 1.5, 5) looking down -Z" "the default camera is named"
contains "defaulted  light: point light at the camera" "the default light is named"
contains "1 concave, ear-clipped" "the concave polygon is counted"
expect 0 "info --json of a bare OBJ" -- "$FOVREF" scene info "$Q/concave-polygon.obj" --json
contains '"defaulted": [' "json lists the defaults"
contains '"concave_polygons": 1' "json counts the concave polygon"

# Every command that takes a scene takes a model file.
expect 0 "render a bare OBJ" -- "$FOVREF" render --scene "$Q/concave-polygon.obj" --mode basic --width 64 --height 36 --out "$TMP/concave"
check_file "$TMP/concave/f000_final.png" "render a bare OBJ"
contains "camera defaulted; light defaulted" "render says what was defaulted, on one line"
expect 0 "export a bare OBJ" -- "$FOVREF" scene export "$Q/backslash-texture.obj" "$TMP/exported"
check_file "$TMP/exported/textures/checker.pfm" "the texture is exported under its '/' name"
expect 0 "reload the export" -- "$FOVREF" scene info "$TMP/exported" --json
contains '"triangles": 2' "the export keeps the triangles"
expect 0 "probe a bare OBJ" -- "$FOVREF" probe --scene "$Q/concave-polygon.obj" --mode basic --width 64 --height 36 --pixel 32,18
contains "bit-identical" "probe agrees with the frame on a bare OBJ"
expect 0 "evaluate a bare OBJ" -- "$FOVREF" evaluate --scene "$Q/concave-polygon.obj" --mode basic --width 32 --height 18 --frames 1 --out "$TMP/ev" -q
check_file "$TMP/ev/rings.csv" "evaluate a bare OBJ"
expect 0 "bench rays on a bare OBJ" -- "$FOVREF" bench rays --scene "$Q/concave-polygon.obj" --width 16 --height 9 --repeats 1
contains "concave-polygon" "bench rays names the model"

# Quirks: warnings by default, one-line errors (exit 2) with --strict-obj.
expect 0 "undefined material" -- "$FOVREF" scene info "$Q/undefined-material.obj"
contains "warning    $Q/undefined-material.obj:13: material 'Chrome' is not defined by any MTL file" "undefined material warns"
expect 2 "undefined material, strict" -- "$FOVREF" scene info --strict-obj "$Q/undefined-material.obj"
contains "undefined-material.obj:13: material 'Chrome' is not defined" "strict names file and line"
checks=$((checks + 1))
if [ "$(wc -l <<<"$OUT")" -ne 1 ]; then echo "FAIL: a strict error is one line: $OUT"; failures=$((failures + 1)); fi
expect 2 "render, strict" -- "$FOVREF" render --strict-obj --scene "$Q/missing-mtl.obj" --mode basic --width 8 --height 8 --out "$TMP/strict"
contains "missing-mtl.obj:2: MTL file 'nowhere.mtl' not found" "render --strict-obj fails on the missing MTL"
expect 0 "missing MTL" -- "$FOVREF" render --scene "$Q/missing-mtl.obj" --mode basic --width 8 --height 8 --out "$TMP/lenient"
contains "warning: $Q/missing-mtl.obj:2: MTL file 'nowhere.mtl' not found" "render prints the first warnings"

# Errors: UTF-16, no triangles; one line each, exit 2.
expect 2 "UTF-16" -- "$FOVREF" render --scene "$Q/utf16.obj" --mode basic --width 8 --height 8 --out "$TMP/utf16"
contains "utf16.obj: the file is UTF-16 text" "UTF-16 says so"
checks=$((checks + 1))
if [ "$(wc -l <<<"$OUT")" -ne 1 ]; then echo "FAIL: the UTF-16 error is one line: $OUT"; failures=$((failures + 1)); fi
expect 2 "lines only" -- "$FOVREF" scene info "$Q/only-lines.obj"
contains "no triangles to render" "lines only"

# --camera: a JSON camera replaces the default one; the default light follows it.
printf '{"camera": {"position": [2, 1.5, 9], "look_at": [2, 1.5, 0], "vfov_deg": 40}}\n' > "$TMP/camera.json"
expect 0 "--camera" -- "$FOVREF" scene info --camera "$TMP/camera.json" "$Q/concave-polygon.obj"
contains "camera     at (2, 1.5, 9)" "--camera sets the camera"
contains "point at (2, 1.5, 9)" "the default light is at that camera"
contains "defaulted  camera: from $TMP/camera.json (--camera)" "--camera is reported"
expect 2 "--camera missing file" -- "$FOVREF" scene info --camera "$TMP/none.json" "$Q/concave-polygon.obj"
printf '{"position": [0, 0, 1],\n "vfov_deg": 40}\n' > "$TMP/bad-camera.json"
expect 2 "--camera malformed" -- "$FOVREF" scene info --camera "$TMP/bad-camera.json" cornell
contains "bad-camera.json:" "a bad camera file names its line"

# The contact sheet of the quirk corpus: every file gets a tile; the refused ones say why.
if command -v rsvg-convert >/dev/null && command -v python3 >/dev/null; then
  expect 1 "contact sheet" -- python3 "$SRC/tools/scripts/contact_sheet.py" "$TMP/sheet.png" "$Q"/*.obj --fovref "$FOVREF" --json "$TMP/sheet.json" --views front,three-quarter
  contains "9 of 11 rendered" "contact sheet: all but UTF-16 and lines-only render"
  check_file "$TMP/sheet.png" "contact sheet PNG"
  expect 0 "contact sheet rows" -- cat "$TMP/sheet.json"
  contains '"status": "refused"' "refused files are listed"
  contains "the file is UTF-16 text" "the refusal's message is kept"
else
  echo "skipped: the contact sheet needs python3 and rsvg-convert (tools/scripts/setup.sh installs them)"
fi

# The installed tool: data found next to the binary, from any directory.
if cmake --install . --prefix "$TMP/prefix" >/dev/null 2>&1; then
  expect 0 "installed --version" -- env -C / "$TMP/prefix/bin/fovref" --version
  contains "data   $TMP/prefix/share/fovref" "the installed tool uses the installed data"
  expect 0 "installed golden verify" -- env -C / "$TMP/prefix/bin/fovref" golden verify --case cornell-geometry --case textured-room-geometry
  contains "2 cases, 0 failed" "installed golden verify"
  expect 0 "installed render of the hand-written scene" -- env -C / "$TMP/prefix/bin/fovref" render --scene scenes/textured-room --mode basic --width 16 --height 9 --out "$TMP/installed-render"
  check_file "$TMP/installed-render/f000_final.png" "installed render"
else
  echo "FAIL: cmake --install of the build directory failed"; failures=$((failures + 1))
fi
finish
