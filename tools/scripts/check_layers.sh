#!/usr/bin/env bash
# Fails when an include in ref/ points up the pipeline (docs/stage-framework.md, "Layers").
# A folder may include its own files and those of folders on lower layers only; folders on the
# same layer are independent of each other. A new stage folder must be added to the table.
#   check_layers.sh [ROOT]     checks ROOT/ref (default: this repository)
#   check_layers.sh --self-test  checks that an upward include and an unknown folder are caught
set -euo pipefail
self="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  mkdir -p "$tmp/ref/core" "$tmp/ref/trace" "$tmp/ref/raster"
  printf '#include "ref/core/a.h"\n' >"$tmp/ref/trace/t.h"
  printf '#pragma once\n' >"$tmp/ref/core/a.h"
  bash "$self" "$tmp" >/dev/null || { echo "self-test: a downward include was refused"; exit 1; }
  printf '#include "ref/trace/t.h"\n' >"$tmp/ref/raster/r.cpp"
  if out=$(bash "$self" "$tmp"); then echo "self-test: raster -> trace not caught"; exit 1; fi
  grep -q 'ref/raster/r.cpp:1: ref/raster (layer 5) includes ref/trace (layer 6)' <<<"$out" ||
    { echo "self-test: unexpected message: $out"; exit 1; }
  rm "$tmp/ref/raster/r.cpp"
  mkdir -p "$tmp/ref/newstage" && printf '\n' >"$tmp/ref/newstage/n.cpp"
  if out=$(bash "$self" "$tmp"); then echo "self-test: an unknown folder was not caught"; exit 1; fi
  grep -q 'folder ref/newstage is in no layer' <<<"$out" ||
    { echo "self-test: unexpected message: $out"; exit 1; }
  echo "check_layers self-test: passed"
  exit 0
fi
cd "${1:-$(dirname "$self")/../..}"

# layer: folders (lowest first)
layers=(
  "core"
  "image"
  "metrics scene"
  "stage"
  "bvh building_blocks golden filters gaze"
  "raster"
  "trace"
  "log_polar frustum"
  "visual_polar"
  "analysis"
  "temporal"
  "bmfr"
  "modes"
)
declare -A layer_of
for i in "${!layers[@]}"; do
  for folder in ${layers[$i]}; do layer_of[$folder]=$i; done
done

status=0
checked=0
files=$(find ref -name '*.h' -o -name '*.cpp' | LC_ALL=C sort)
for file in $files; do
  folder=${file#ref/}
  folder=${folder%%/*}
  if [ -z "${layer_of[$folder]+x}" ]; then
    echo "check_layers: $file: folder ref/$folder is in no layer (add it to tools/scripts/check_layers.sh and docs/stage-framework.md)"
    status=1
  fi
done
# One grep over every file: lines "FILE:LINE:#include "ref/FOLDER/...""
pattern='^(ref/([^/]+)/[^:]+):([0-9]+):.*"ref/([^/]+)/'
while IFS= read -r hit; do
  [[ $hit =~ $pattern ]] || continue
  file=${BASH_REMATCH[1]} folder=${BASH_REMATCH[2]} line=${BASH_REMATCH[3]} target=${BASH_REMATCH[4]}
  checked=$((checked + 1))
  [ "$target" = "$folder" ] && continue
  [ -z "${layer_of[$folder]+x}" ] && continue  # reported above
  mine=${layer_of[$folder]}
  if [ -z "${layer_of[$target]+x}" ]; then
    echo "check_layers: $file:$line includes ref/$target, which is in no layer"
    status=1
  elif [ "${layer_of[$target]}" -ge "$mine" ]; then
    echo "check_layers: $file:$line: ref/$folder (layer $mine) includes ref/$target (layer ${layer_of[$target]}): includes must point down the pipeline"
    status=1
  fi
done < <(grep -n -H -E '^[[:space:]]*#[[:space:]]*include[[:space:]]*"ref/' $files || true)
if [ "$status" -ne 0 ]; then exit 1; fi
echo "layers: $checked includes in ref/ point down"
