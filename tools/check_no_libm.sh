#!/usr/bin/env bash
# SPEC §0: the renderer library imports none of libm's transcendental functions. Lists the
# undefined symbols of the static library and fails on any of them.
set -euo pipefail
lib=$1
pattern='^(exp|exp2|expm1|log|log2|log10|log1p|pow|sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|asinh|acosh|atanh|erf|erfc|tgamma|lgamma|cbrt|hypot|sincos)(f|l)?(@.*)?$|^__(exp|log|pow|sin|cos|atan2|acos|asin)(f)?_finite'
found=$(nm -u "$lib" | awk '{print $NF}' | sort -u | grep -E "$pattern" || true)
if [ -n "$found" ]; then
  echo "libm transcendental functions imported by $lib:"
  echo "$found"
  exit 1
fi
echo "no libm transcendental imports in $(basename "$lib") ($(nm -u "$lib" | awk '{print $NF}' | sort -u | wc -l) undefined symbols checked)"
