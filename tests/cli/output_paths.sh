# Output directories are checked before any work and written through a staging directory, so a
# bad path fails at once and a failure leaves nothing behind (tools/cli/common/output_dir.h); and
# the small usability fixes of issue 29: parameters, JSON pointers, diff's extensions, --help.
source "$(dirname "$0")/lib.bash"
cd "$TMP" || exit 1
touch afile
# nothing_new WHAT: the working directory holds only afile (no folder, no staging left behind).
nothing_new() {
  checks=$((checks + 1))
  local left; left=$(ls -A | grep -v '^afile$')
  if [ -n "$left" ]; then echo "FAIL: $1: left behind: $left"; failures=$((failures + 1)); rm -rf -- $left; fi
}

expect 2 "evaluate --out FILE" -- "$FOVREF" evaluate --scene cornell --mode fov --width 64 --height 36 --frames 1 --out afile -q
contains "--out afile: exists and is not a directory" "names the option and the file"
nothing_new "evaluate --out FILE"
expect 2 "density --out FILE" -- "$FOVREF" density cfov --out afile
contains "--out afile: exists and is not a directory" "density names it"
checks=$((checks + 1)); if grep -q "ring" <<<"$OUT"; then echo "FAIL: density printed its table before failing"; failures=$((failures + 1)); fi
expect 2 "render --out X --dump X" -- "$FOVREF" render --scene cornell --mode basic --width 16 --height 9 --out same --dump same -q
contains "--out and --dump name the same directory" "same directory refused"
nothing_new "render --out X --dump X"
expect 2 "render --out X --dump X/d" -- "$FOVREF" render --scene cornell --mode basic --width 16 --height 9 --out same --dump same/d -q
contains "--dump same/d lies inside --out same" "nested refused"
nothing_new "render --out X --dump X/d"
expect 2 "render --out below a file" -- "$FOVREF" render --scene cornell --mode basic --width 16 --height 9 --out afile/x -q
contains "afile is not a directory" "a file on the way"
# A failure after the check (a bad parameter) creates nothing: no folder on the way, no staging
expect 2 "density, bad parameter" -- "$FOVREF" density cfov --param sigma=-1 --out new/sub -q
nothing_new "density that fails"
expect 2 "evaluate, bad mode" -- "$FOVREF" evaluate --scene cornell --mode nosuchmode --width 64 --height 36 --frames 1 --out new/ev -q
nothing_new "evaluate that fails"
expect 0 "density --out new/sub" -- "$FOVREF" density cfov --out new/sub -q
check_file new/sub/density.csv "density.csv in a new nested directory"
checks=$((checks + 1)); if ls -A new | grep -q writing; then echo "FAIL: staging directory left"; failures=$((failures + 1)); fi
rm -rf new

# Parameters: beyond the float range, given twice
expect 2 "alpha=1e40" -- "$FOVREF" render --scene cornell --mode fov --width 16 --height 9 --param alpha=1e40 --out r -q
contains "parameter 'alpha': 1e40 is outside [1, 64] (beyond the float range)" "out of range, not 'not a finite number'"
expect 2 "a parameter given twice" -- "$FOVREF" render --scene cornell --mode fov --width 16 --height 9 --param alpha=2 --param alpha=3 --out r -q
contains "parameter 'alpha' is given twice (alpha=2, alpha=3)" "repeated --param refused"
nothing_new "parameter errors"
# A scene file missing a top-level key: the document, not an empty JSON pointer
echo '{}' > bare.json
expect 2 "scene file without version" -- "$FOVREF" scene info bare.json
contains "bare.json:1: the document: missing key \"version\"" "the document named"
rm bare.json
# diff: a candidate without extension lists every extension it reads
expect 0 "golden export" -- "$FOVREF" golden export cornell-basic g -q
echo x > noext
expect 2 "diff of a file without extension" -- "$FOVREF" diff g noext
contains "(expected .pfm, .exr, .png, .raw, .bin, .f32;" "raw extensions listed"
rm -rf g noext
# --help: the command list only in fovref --help; sweep's description on sweep's line
expect 0 "render --help" -- "$FOVREF" render --help
checks=$((checks + 1)); if grep -q "fovref scene list" <<<"$OUT"; then echo "FAIL: render --help ends with the global command list"; failures=$((failures + 1)); fi
expect 0 "fovref --help" -- "$FOVREF" --help
checks=$((checks + 1))
if ! grep -A3 "fovref sweep plan" <<<"$OUT" | grep -B1 "fovref stress" | grep -q "run time against error"; then
  echo "FAIL: sweep's description is not under sweep"; failures=$((failures + 1)); fi
expect 0 "modes" -- "$FOVREF" modes
checks=$((checks + 1)); if grep -q "(Meng 2018) (Meng 2018" <<<"$OUT"; then echo "FAIL: kfr's source twice"; failures=$((failures + 1)); fi
contains "pathtrace-reference the converged" "the names' column as wide as the longest name"
expect 0 "golden list" -- "$FOVREF" golden list
checks=$((checks + 1))
if [ "$(awk '{match($0, /^[^ ]+ +/); print RLENGTH}' <<<"$OUT" | sort -u | wc -l)" -ne 1 ]; then echo "FAIL: golden list's mode column shifts"; failures=$((failures + 1)); fi
# The scripts are executable, and the contact sheet without a fovref says so
for s in "$SRC"/tools/scripts/*.sh "$SRC"/tools/scripts/*.py; do
  checks=$((checks + 1)); [ -x "$s" ] || { echo "FAIL: $s is not executable"; failures=$((failures + 1)); }
done
expect 2 "contact sheet without fovref" -- env PATH=/usr/bin:/bin python3 "$SRC/tools/scripts/contact_sheet.py" sheet.png x.obj --fovref ./nofovref
contains "contact_sheet: no fovref binary at './nofovref'" "a clear message, no traceback"
finish
