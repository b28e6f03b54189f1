#!/usr/bin/env bash
# fovref test command: builds three configurations and runs every test in each.
#   build/gcc-O2     g++ -O2            (the default build)
#   build/clang-O0   clang++ -O0        (the goldens must verify bit-exactly in both)
#   build/asan       g++ -O1 with AddressSanitizer + UndefinedBehaviorSanitizer
# It also checks formatting with the checked-in .clang-format.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${FOVREF_JOBS:-$(nproc)}

configure() {  # dir compiler build-type extra...
  local dir=$1 cxx=$2 type=$3; shift 3
  cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="$type" "$@" >/dev/null
}

echo "== format check"
bash tools/check_format.sh

status=0
run_suite() {  # dir label
  echo "== $2: build"
  cmake --build "$1" -j "$jobs"
  echo "== $2: tests"
  if ! ctest --test-dir "$1" --output-on-failure -j "$jobs"; then status=1; fi
}

configure build/gcc-O2 g++ Release
run_suite build/gcc-O2 "g++ -O2"
configure build/clang-O0 clang++ Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0
run_suite build/clang-O0 "clang++ -O0"
configure build/asan g++ Debug -DFOVREF_SANITIZE=ON -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  run_suite build/asan "g++ ASan+UBSan"

if [ $status -ne 0 ]; then echo "test: FAILED"; exit 1; fi
echo "test: all suites passed"
