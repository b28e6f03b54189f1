#!/usr/bin/env bash
# Every doctest case must run under ctest. doctest_discover_tests registers one ctest entry per
# test case, reading the names as a CMake list: a ';' in a name splits it into names that match
# no case, and their entries then pass without running anything (51 cases did, until
# 2026-11-29). Fails on any such name, and on a binary that lists no case at all.
#   check_test_names.sh TESTS     check the cases of a doctest binary (--list-test-cases)
#   check_test_names.sh --self-test  prove the check catches a name with ';'
set -euo pipefail

check() {
  local names bad
  # the names lie between doctest's banner lines ("[doctest] ...", "=====...")
  names=$("$@" --list-test-cases | grep -v -e '^\[doctest\]' -e '^=====' || true)
  if [ -z "$names" ]; then echo "check_test_names: $* listed no test case"; return 1; fi
  bad=$(grep ';' <<<"$names" || true)
  if [ -n "$bad" ]; then
    echo "test case names with ';', which ctest splits into entries that run nothing (use ','):"
    echo "$bad"
    return 1
  fi
  echo "$(wc -l <<<"$names") test case names, none with ';'"
}

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
  printf '#!/usr/bin/env bash\necho "[doctest] listing all test case names"\necho =====\necho "a: fine"\necho "b: one; two"\necho =====\n' > "$tmp/tests"
  if check bash "$tmp/tests" >/dev/null; then echo "self-test FAILED: a name with ';' was not detected"; exit 1; fi
  echo "self-test passed: a name with ';' is detected"
  exit 0
fi
check "$1"
