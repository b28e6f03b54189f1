#!/usr/bin/env bash
# Fails when a C++ source differs from the checked-in .clang-format style.
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files 'ref/*.h' 'ref/*.cpp' 'tests/*.cpp' 'tests/*.h' 'tools/*.cpp' 'tools/*.h' 2>/dev/null || true)
[ -n "$files" ] || exit 0
clang-format --dry-run -Werror $files
