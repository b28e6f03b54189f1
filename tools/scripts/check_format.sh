#!/usr/bin/env bash
# Fails when a C++ source differs from the checked-in .clang-format style.
set -euo pipefail
cd "$(dirname "$0")/../.."
# safe.directory: CI may run as another user than the clone's owner.
files=$(git -c safe.directory="$PWD" ls-files 'ref/*.h' 'ref/*.cpp' 'tests/*.cpp' 'tests/*.h' 'tools/*.cpp' 'tools/*.h')
if [ -z "$files" ]; then echo "check_format: no sources found (is this a git checkout?)"; exit 1; fi
clang-format --dry-run -Werror $files
echo "format: $(wc -w <<<"$files") files clean"
