#!/usr/bin/env bash
# fovref test command: builds three configurations (the presets of CMakePresets.json) and runs
# every test in each.
#   release  build/gcc-O2     g++ -O2            (the default build)
#   debug    build/clang-O0   clang++ -O0 -g     (the goldens must verify bit-exactly in both;
#                                                 the debugger test runs here; this build runs
#                                                 those two, the other two builds every test)
#   asan     build/asan       clang++ -O1 -gline-tables-only with AddressSanitizer +
#                             UndefinedBehaviorSanitizer (their reports name lines); the same
#                             build holds the libFuzzer targets (one per loader), run with a
#                             fixed seed and a fixed number of executions (tools/scripts/fuzz.sh
#                             --ci, about a minute)
# The OpenGL and Vulkan clients (never sanitized) are built and tested in the release build only.
# It also checks formatting with the checked-in .clang-format, and prints the time elapsed at
# each step (CI must finish within 25 minutes on a 2-core machine).
set -euo pipefail
cd "$(dirname "$0")/../.."
jobs=${FOVREF_JOBS:-$(nproc)}
elapsed() { printf '%d:%02d' $((SECONDS / 60)) $((SECONDS % 60)); }

configure() {  # preset
  cmake --preset "$1" >/dev/null
}

echo "== format check"
bash tools/scripts/check_format.sh
bash tools/scripts/check_layers.sh

status=0
# The tests also wait on files and child processes: one more job than cores keeps both busy.
run_suite() {  # dir label
  echo "== $2: build (at $(elapsed))"
  cmake --build "$1" -j "$jobs"
  echo "== $2: tests (at $(elapsed))"
  if ! ctest --test-dir "$1" --output-on-failure -j $((jobs + 1)); then status=1; fi
}

configure release
run_suite build/gcc-O2 "g++ -O2"
# The -O0 build's two tests (one of them a single-threaded golden verify, the other mostly
# waiting on gdb) leave a core idle for their whole run: they run while the ASan build compiles,
# their output held in a log and printed after them.
configure debug
echo "== clang++ -O0 -g: build (at $(elapsed))"
cmake --build build/clang-O0 -j "$jobs" --target fovref_cli
echo "== clang++ -O0 -g: tests, alongside the ASan build (from $(elapsed))"
o0_log=build/clang-O0/ctest-ci.log
# (setsid: a process group of their own, so that an early exit stops the tests too, not only ctest)
setsid ctest --test-dir build/clang-O0 --output-on-failure -j 2 \
  -R '^cli\.(golden_verify|debugger)$' >"$o0_log" 2>&1 &
o0_tests=$!
trap 'kill -- -"$o0_tests" 2>/dev/null || true' EXIT
configure asan
echo "== clang++ ASan+UBSan: build (at $(elapsed))"
cmake --build build/asan -j "$jobs"
o0_status=0
wait "$o0_tests" || o0_status=$?
trap - EXIT
echo "== clang++ -O0 -g: tests done (at $(elapsed))"
cat "$o0_log"
if [ $o0_status -ne 0 ]; then status=1; fi
echo "== clang++ ASan+UBSan: tests (at $(elapsed))"
if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j $((jobs + 1)); then status=1; fi

echo "== fuzz: run (fixed seed; the targets of build/asan) (at $(elapsed))"
if ! bash tools/scripts/fuzz.sh --ci; then status=1; fi

if [ $status -ne 0 ]; then echo "test: FAILED"; exit 1; fi
echo "test: all suites passed ($(elapsed))"
