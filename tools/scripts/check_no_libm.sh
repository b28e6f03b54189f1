#!/usr/bin/env bash
# SPEC §0: the renderer library imports none of libm's transcendental functions. Lists the
# undefined symbols of the static library and fails on any of them.
#   check_no_libm.sh LIBRARY      check a library or object
#   check_no_libm.sh --self-test  prove the check catches a call to sinf
set -euo pipefail
pattern='^(exp|exp2|expm1|log|log2|log10|log1p|pow|sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|asinh|acosh|atanh|erf|erfc|tgamma|lgamma|cbrt|hypot|sincos)(f|l)?(@.*)?$|^__(exp|log|pow|sin|cos|atan2|acos|asin)(f)?_finite'

check() {
  local lib=$1 symbols found
  symbols=$(nm -u "$lib" | awk '{print $NF}' | sort -u)
  if [ -z "$symbols" ]; then echo "check_no_libm: nm listed no undefined symbols in $lib"; return 1; fi
  found=$(grep -E "$pattern" <<<"$symbols" || true)
  if [ -n "$found" ]; then
    echo "libm transcendental functions imported by $lib:"
    echo "$found"
    return 1
  fi
  echo "no libm transcendental imports in $(basename "$lib") ($(wc -l <<<"$symbols") undefined symbols checked)"
}

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
  printf '#include <cmath>\nfloat f(float x) { return std::sin(x) + std::sqrt(x); }\n' > "$tmp/t.cpp"
  ${CXX:-c++} -O2 -c "$tmp/t.cpp" -o "$tmp/t.o"
  if check "$tmp/t.o" >/dev/null; then echo "self-test FAILED: a call to sinf was not detected"; exit 1; fi
  echo "self-test passed: a call to sinf is detected"
  exit 0
fi
check "$1"
