# A golden that differs from this build is reported with its buffer and first differing pixel.
source "$(dirname "$0")/lib.bash"
mkdir -p "$TMP/golden"
cat > "$TMP/golden/cases.json" <<'JSON'
{"cases": [{"name": "tiny-rng", "mode": "rng", "width": 6, "height": 4, "frames": 1},
           {"name": "tiny-halton", "mode": "halton", "width": 16, "height": 1}]}
JSON
expect 1 "verify without bundles" -- "$FOVREF" golden verify --dir "$TMP/golden"
contains "no bundle" "verify without bundles"
expect 0 "update" -- "$FOVREF" golden update --dir "$TMP/golden"
contains "updated tiny-rng: new" "update says what changed"
expect 0 "verify after update" -- "$FOVREF" golden verify --dir "$TMP/golden"
expect 0 "update again" -- "$FOVREF" golden update --dir "$TMP/golden"
contains "updated tiny-rng: unchanged" "update again"

# Pretend another build produced a different value: change the stored file's last float (the
# top row's last pixel, channel 2: PFM rows are bottom-to-top) and its hash in the manifest.
pfm="$TMP/golden/tiny-rng/f000_rng.pfm"
size=$(stat -c %s "$pfm")
printf '\x41' | dd of="$pfm" bs=1 seek=$((size - 1)) conv=notrunc status=none
sed -i '0,/"sha256": "[0-9a-f]*"/s//"sha256": "0000000000000000000000000000000000000000000000000000000000000000"/' \
  "$TMP/golden/tiny-rng/manifest.json"
expect 1 "verify a perturbed golden" -- "$FOVREF" golden verify --dir "$TMP/golden"
contains "FAIL tiny-rng" "perturbed golden names the case"
contains "buffer rng" "perturbed golden names the buffer"
contains "pixel (5, 0) channel d2" "perturbed golden names the first pixel"
contains "ok   tiny-halton" "other cases still pass"

expect 2 "unknown case" -- "$FOVREF" golden verify --dir "$TMP/golden" --case nope
expect 2 "too large for the repository" -- bash -c "printf '%s' '{\"cases\": [{\"name\": \"big\", \"mode\": \"rng\", \"width\": 640, \"height\": 360}]}' > '$TMP/golden/cases.json' && '$FOVREF' golden update --dir '$TMP/golden'"
contains "320x180" "size limit"
finish
