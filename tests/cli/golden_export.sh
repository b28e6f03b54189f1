# golden export writes a full bundle at any size.
source "$(dirname "$0")/lib.bash"
expect 0 "list" -- "$FOVREF" golden list --dir "$SRC/golden"
contains "cornell-splat" "list"
expect 0 "export" -- "$FOVREF" golden export cornell-splat "$TMP/bundle" --width 64 --height 36 --frames 2 \
  --dir "$SRC/golden" --quiet
check_file "$TMP/bundle/manifest.json" "export manifest"
grep -q '"width": 64' "$TMP/bundle/manifest.json" || { echo "FAIL: export width"; failures=$((failures+1)); }
for b in splat_depth splat_primitive splat_normal splat_albedo final; do
  check_file "$TMP/bundle/f001_$b.pfm" "export $b"
  check_file "$TMP/bundle/f001_$b.png" "export preview $b"
done
expect 2 "export unknown case" -- "$FOVREF" golden export nope "$TMP/x" --dir "$SRC/golden"
finish
