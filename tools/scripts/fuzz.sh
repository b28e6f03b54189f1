#!/usr/bin/env bash
# fovref fuzzing with libFuzzer: one target per loader (tests/fuzz/fuzz_*.cpp), built by the
# `asan` preset (clang++ with -fsanitize=fuzzer,address,undefined) into build/asan.
#
#   tools/scripts/fuzz.sh --ci                 every target, a fixed seed and a fixed number of runs
#                                      (about a minute in all); the test command runs this
#   tools/scripts/fuzz.sh --minutes N [T...]   each target (or the named ones) for N minutes, with a
#                                      corpus kept in build/asan/corpus/<target> between runs
#
# Seeds: the repository's own files (golden bundles, the hand-written scene, golden/cases.json),
# files the release build's fovref writes (scene exports, ray files), and the regression inputs
# of tests/fuzz/regressions/<target> (every finding of the hardening issue; each is also run once
# on its own). A crash, a sanitizer report, an exception other than fovref::Error, a timeout
# (10 s) or a leak fails the run; the input is left in build/asan/artifacts/ and named here.
set -euo pipefail
cd "$(dirname "$0")/../.."

mode=ci
minutes=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --ci) mode=ci ;;
    --minutes) mode=long; minutes=${2:?--minutes needs a number}; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    fuzz_*) targets+=("$1") ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)"; exit 2 ;;
  esac
  shift
done

build=build/asan
if [ ! -x "$build/fuzz_pfm" ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan --target fuzzers
fi
fovref=build/gcc-O2/fovref
if [ ! -x "$fovref" ]; then
  cmake --preset release >/dev/null
  cmake --build --preset release --target fovref_cli
fi
if [ ${#targets[@]} -eq 0 ]; then
  for t in "$build"/fuzz_*; do [ -x "$t" ] && targets+=("$(basename "$t")"); done
fi

# ---- Seed corpora ----
seeds="$build/seeds"
rm -rf "$seeds"
mkdir -p "$seeds"
make_seeds() {
  local s=$seeds
  mkdir -p "$s"/{fuzz_pfm,fuzz_png,fuzz_exr,fuzz_raw,fuzz_scene_json,fuzz_obj,fuzz_texture,fuzz_rays,fuzz_tolerance,fuzz_manifest,fuzz_cases,fuzz_gaze_track,fuzz_gltf}
  local k=0
  for f in golden/*/*.pfm; do [ $((k++ % 7)) -eq 0 ] && [ "$(stat -c %s "$f")" -lt 65536 ] && cp "$f" "$s/fuzz_pfm/$(echo "$f" | tr / _)"; done
  for f in golden/*/*.png scenes/textured-room/*.png; do [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 65536 ] && cp "$f" "$s/fuzz_png/$(echo "$f" | tr / _)"; done
  for f in golden/*/*.exr; do [ "$(stat -c %s "$f")" -lt 65536 ] && cp "$f" "$s/fuzz_exr/$(echo "$f" | tr / _)"; done
  for f in golden/*/manifest.json; do [ "$(stat -c %s "$f")" -lt 65536 ] && cp "$f" "$s/fuzz_manifest/$(echo "$f" | tr / _)"; done
  cp golden/cases.json "$s/fuzz_cases/"
  # Raw: a layout header (4 bytes) and a matching payload.
  printf '\x03\x01\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x00\x00\x80\x40\x00\x00\xa0\x40\x00\x00\xc0\x40\x00\x00\xe0\x40\x00\x00\x00\x41' > "$s/fuzz_raw/4x2x1"
  # Scenes: the hand-written one and exports of procedural ones (JSON, OBJ + MTL, textures).
  cp scenes/textured-room/scene.json "$s/fuzz_scene_json/textured-room.json"
  for scene in cornell checker-room; do
    "$fovref" scene export "$scene" "$build/export-$scene" -q
    cp "$build/export-$scene/scene.json" "$s/fuzz_scene_json/$scene.json"
    { cat "$build/export-$scene/scene.obj"; echo "#--mtl--"; cat "$build/export-$scene/scene.mtl"; } > "$s/fuzz_obj/$scene"
  done
  for f in scenes/textured-room/*.obj; do cp "$f" "$s/fuzz_obj/$(basename "$f")"; done
  # The OBJ quirk corpus (docs/obj-quirks.md), each OBJ with the MTL file it names, if any.
  for f in tests/scene/obj-quirks/*.obj; do
    mtl=$(sed -n 's/^mtllib \(.*\)$/\1/p' "$f" | head -1)
    # The target's MTL file is mesh.mtl.
    { sed 's/^mtllib .*/mtllib mesh.mtl/' "$f"; if [ -n "$mtl" ] && [ -f "tests/scene/obj-quirks/$mtl" ]; then
        echo; echo "#--mtl--"; cat "tests/scene/obj-quirks/$mtl"; fi; } > "$s/fuzz_obj/quirk-$(basename "$f")"
  done
  for f in "$build"/export-checker-room/textures/*.pfm; do { printf '\x01'; cat "$f"; } > "$s/fuzz_texture/$(basename "$f")"; done
  for f in scenes/textured-room/*.png; do [ -f "$f" ] && { printf '\x00'; cat "$f"; } > "$s/fuzz_texture/$(basename "$f")"; done
  # Ray and hit files.
  "$fovref" rays make cornell "$s/fuzz_rays/random.rays" --random 16 --seed 3 -q
  "$fovref" rays trace cornell "$s/fuzz_rays/random.rays" "$s/fuzz_rays/random.hits" -q
  # Tolerance files.
  printf '{\n  "final": {"ulp": 4, "reason": "GPU pow"},\n  "gbuffer_primitive_id": {"edge_mismatch_share": 0.01, "interior_mismatches": 0},\n  "*": {"abs": 1e-6, "rel": 1e-4, "max_failing_pixels": 3}\n}\n' > "$s/fuzz_tolerance/file.json"
  printf 'final:abs=1e-5,ulp=4,pixels=10' > "$s/fuzz_tolerance/option"
  # glTF: a triangle with material, texture (tex.png, written by the target), camera and point
  # light: as .gltf with a data: URI buffer, with buffer.bin after "#--bin--", and as .glb.
  local tri='\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x01\x00\x02\x00'
  local gltf_head='{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1,2]}],"nodes":[{"mesh":0,"translation":[0,0,-1]},{"camera":0,"rotation":[0,0,0,1]},{"extensions":{"KHR_lights_punctual":{"light":0}}}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0,"mode":4}]}],"materials":[{"name":"m","pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0.5,1],"metallicFactor":0,"roughnessFactor":0.5,"baseColorTexture":{"index":0}},"emissiveFactor":[0,0,0]}],"textures":[{"source":0,"sampler":0}],"samplers":[{"wrapS":10497,"wrapT":10497}],"images":[{"uri":"tex.png"}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.1}}],"extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","intensity":2}]}},"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":42'
  printf '%s,"uri":"data:application/octet-stream;base64,%s"}]}' "$gltf_head" "$(printf "$tri" | base64 -w0)" > "$s/fuzz_gltf/data-uri.gltf"
  { printf '%s,"uri":"buffer.bin"}]}\n#--bin--\n' "$gltf_head"; printf "$tri"; } > "$s/fuzz_gltf/external-bin"
  local glb_json glb_pad
  le32() { printf '\\x%02x\\x%02x\\x%02x\\x%02x' $(($1 & 255)) $((($1 >> 8) & 255)) $((($1 >> 16) & 255)) $((($1 >> 24) & 255)); }
  glb_json="$gltf_head}]}"
  glb_pad=$(( (4 - ${#glb_json} % 4) % 4 ))
  glb_json="$glb_json$(printf '%*s' "$glb_pad" '')"
  { printf 'glTF'; printf "$(le32 2)$(le32 $((12 + 8 + ${#glb_json} + 8 + 44)))$(le32 ${#glb_json})JSON"; printf '%s' "$glb_json"
    printf "$(le32 44)BIN\\x00"; printf "$tri"; printf '\x00\x00'; } > "$s/fuzz_gltf/triangle.glb"
  # The shipped glTF (node tree, strip, fan, embedded PNG, camera, lights; data: URI buffer).
  cp scenes/model-files/nodes.gltf "$s/fuzz_gltf/nodes.gltf"
  # Gaze tracks.
  printf 'frame,x,y\n# eye tracker, 120 Hz\n0,640,360\n3,612.5,340.25\n10,-20,1e3\n' > "$s/fuzz_gaze_track/track.csv"
}
make_seeds
dictionary() {
  case "$1" in
    fuzz_scene_json|fuzz_tolerance|fuzz_manifest|fuzz_cases|fuzz_gltf) echo "-dict=tests/fuzz/dict/json.dict" ;;
    fuzz_obj) echo "-dict=tests/fuzz/dict/obj.dict" ;;
    fuzz_pfm|fuzz_raw) echo "-dict=tests/fuzz/dict/pfm.dict" ;;
    fuzz_png|fuzz_texture) echo "-dict=tests/fuzz/dict/png.dict" ;;
  esac
}
# Runs per target in --ci: about 5 seconds each on 2 cores under ASan.
ci_runs() {
  case "$1" in
    fuzz_scene_json|fuzz_obj|fuzz_texture|fuzz_gltf) echo 3000 ;;
    fuzz_exr|fuzz_manifest) echo 4000 ;;
    *) echo 8000 ;;
  esac
}

artifacts="$build/artifacts"
mkdir -p "$artifacts"
status=0
summary=()
for t in "${targets[@]}"; do
  exe="$build/$t"
  [ -x "$exe" ] || { echo "fuzz.sh: no target $t in $build"; exit 2; }
  regressions=tests/fuzz/regressions/$t
  # 1. Every regression input once.
  if [ -d "$regressions" ] && [ -n "$(ls -A "$regressions")" ]; then
    if ! "$exe" -timeout=10 -rss_limit_mb=2048 "$regressions"/* >"$build/$t.regressions.log" 2>&1; then
      echo "FAIL: $t on its regression inputs (log: $build/$t.regressions.log)"
      tail -20 "$build/$t.regressions.log"; status=1
    fi
  fi
  # 2. Fuzzing from the seeds.
  if [ "$mode" = ci ]; then
    corpus=$(mktemp -d)
    limits=(-seed=1 -runs="$(ci_runs "$t")")
  else
    corpus="$build/corpus/$t"
    mkdir -p "$corpus"
    limits=(-max_total_time=$((minutes * 60)))
  fi
  log="$build/$t.log"
  start=$(date +%s)
  # shellcheck disable=SC2046
  if "$exe" "${limits[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
       -artifact_prefix="$artifacts/$t-" $(dictionary "$t") "$corpus" "$seeds/$t" \
       $( [ -d "$regressions" ] && echo "$regressions" ) >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    summary+=("$(printf '%-18s %10s runs %5ss  ok' "$t" "$runs" "$(( $(date +%s) - start ))")")
  else
    status=1
    summary+=("$(printf '%-18s FAILED (log %s; input in %s)' "$t" "$log" "$artifacts")")
    grep -E "ERROR|SUMMARY|Test unit written|deadly signal|uncaught exception" "$log" | head -10
  fi
  [ "$mode" = ci ] && rm -rf "$corpus"
done
echo "fuzz ($mode$( [ "$mode" = long ] && echo ", $minutes min per target" )):"
printf '  %s\n' "${summary[@]}"
[ $status -eq 0 ] && echo "fuzz: no findings" || echo "fuzz: FINDINGS (see above)"
exit $status
