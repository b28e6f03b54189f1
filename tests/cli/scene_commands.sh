# scene list/info/export, good and bad inputs.
source "$(dirname "$0")/lib.bash"
expect 0 "scene list" -- "$FOVREF" scene list
for s in cornell sphere-grid million checker-room glossy-floor; do contains "$s" "scene list"; done

expect 0 "info cornell" -- "$FOVREF" scene info cornell
contains "triangles" "info cornell"
contains "lights" "info cornell"
contains "zero-area" "info cornell"
expect 0 "info hand-written scene" -- "$FOVREF" scene info "$SRC/scenes/textured-room/scene.json"
contains "textures   1" "info hand-written scene"
expect 0 "info json" -- "$FOVREF" scene info cornell --json
contains '"triangles"' "info json"

expect 2 "missing scene file" -- "$FOVREF" scene info "$TMP/nope.json"
contains "nope.json" "missing scene file"
printf '{\n  "camera": {\n    "position": [0, 0, oops]\n  }\n}\n' > "$TMP/bad.json"
expect 2 "malformed scene" -- "$FOVREF" scene info "$TMP/bad.json"
contains "bad.json:3" "malformed scene names file and line"

# Export round trip: the exported scene has the same triangle count.
for s in cornell checker-room; do
  expect 0 "info $s" -- "$FOVREF" scene info "$s" --json
  before=$(grep '"triangles"' <<<"$OUT")
  expect 0 "export $s" -- "$FOVREF" scene export "$s" "$TMP/$s"
  check_file "$TMP/$s/scene.json" "export $s"
  expect 0 "info exported $s" -- "$FOVREF" scene info "$TMP/$s/scene.json" --json
  contains "$before" "exported $s keeps its triangles"
done
expect 2 "export to an unwritable place" -- "$FOVREF" scene export cornell /proc/fovref-cannot-write
finish
