# fovref sweep (issue 17): plan a small sweep, run it locally, merge; rerun skips finished jobs and
# redoes a removed one; the same sweep through GNU parallel merges to the same results (timing
# columns aside); the Slurm and Kubernetes exports; bad sweep files are refused with file, line
# and JSON pointer, and nothing is written.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

cat > "$TMP/sweep.json" <<'JSON'
{
  "scenes": ["cornell"],
  "resolutions": ["48x27"],
  "frames": 2,
  "repeats": 2,
  "flip": true,
  "configurations": [
    {"mode": "basic"},
    {"mode": "fov", "grid": {"sigma": [1.4, 1.8]}, "params": {"alpha": 1}}
  ]
}
JSON
expect 0 "plan" -- "$FOVREF" sweep plan "$TMP/sweep.json" "$TMP/a"
contains "1 reference job(s) and 3 evaluation job(s)" "jobs counted"
check_file "$TMP/a/plan.json" "plan.json"
expect 0 "plan again: the same ids" -- "$FOVREF" sweep plan "$TMP/sweep.json" "$TMP/a2"
checks=$((checks + 1))
if ! cmp -s <(grep '"id"' "$TMP/a/plan.json") <(grep '"id"' "$TMP/a2/plan.json"); then
  echo "FAIL: job ids are not stable"; failures=$((failures + 1))
fi

expect 0 "run with 2 processes" -- "$FOVREF" sweep run "$TMP/a" --jobs 2
contains "[4/4] ok" "every job ran"
expect 0 "merge" -- "$FOVREF" sweep merge "$TMP/a"
contains "3 result(s), 0 missing" "merged"
check_file "$TMP/a/results.csv" "results.csv"
check_file "$TMP/a/results.json" "results.json"
"$PY" - "$TMP/a" <<'PYTHON' || { echo "FAIL: results content"; failures=$((failures + 1)); }
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/results.csv")))
assert len(rows) == 3, rows
modes = sorted((r["mode"], r["params"]) for r in rows)
assert modes == [("basic", ""), ("fov", "alpha=1 sigma=1.4"), ("fov", "alpha=1 sigma=1.8")], modes
for r in rows:
    assert r["status"] == "done", r
    assert 5 < float(r["psnr"]) < 80 and 0 < float(r["ssim"]) <= 1, r
    assert float(r["rays_traced_per_frame"]) > 0 and float(r["seconds_per_frame"]) > 0, r
    stages = dict(kv.split("=") for kv in r["stage_seconds"].split())
    assert stages and all(float(v) >= 0 for v in stages.values()), r
    assert ("lp_trace" in stages) == (r["mode"] == "fov"), r
basic = [r for r in rows if r["mode"] == "basic"][0]
fov = [r for r in rows if r["mode"] == "fov"]
# the foveated configurations trace fewer rays than basic, and more with the smaller sigma
assert all(float(f["rays_traced_per_frame"]) < float(basic["rays_traced_per_frame"]) for f in fov)
s14 = [f for f in fov if "1.4" in f["params"]][0]; s18 = [f for f in fov if "1.8" in f["params"]][0]
assert float(s14["rays_traced_per_frame"]) > float(s18["rays_traced_per_frame"])
j = json.load(open(sys.argv[1] + "/results.json"))
first = j["results"][0]
assert len(first["ring_psnr"]) == 20 and first["command"].startswith("fovref evaluate"), first
assert "--repeats 2" in first["command"] and first["counters_per_frame"]["pixels_shaded"] > 0, first
assert len(first["ring_flip"]) == 20 and all(0 <= v <= 1 for v in first["ring_flip"] if v is not None), first
assert 0 < float(rows[0]["flip_mean"]) < 1, rows[0]
fov_counters = [r["counters_per_frame"] for r in j["results"] if r["mode"] == "fov"][0]
assert fov_counters["texels_off_screen"] > 0, fov_counters  # work skipped is reported
PYTHON

# The report: one group, three configurations; the front is computed from the merged numbers
# (checked here independently), every plot as SVG (and PNG with rsvg-convert); Chromium renders it.
expect 0 "report" -- "$FOVREF" sweep report "$TMP/a" --html "$TMP/report"
check_file "$TMP/report/index.html" "report page"
"$PY" - "$TMP/a" "$TMP/report" <<'PYTHON' || { echo "FAIL: report content"; failures=$((failures + 1)); }
import json, re, sys, os
rows = json.load(open(sys.argv[1] + "/results.json"))["results"]
page = open(sys.argv[2] + "/index.html").read()
# independent Pareto front on (ms per frame, PSNR)
pts = [(r["seconds_per_frame"], r["psnr"], r["mode"] + "".join(" %s=%s" % kv for kv in sorted(r["params"].items()))) for r in rows]
front = sorted(l for (t, q, l) in pts if not any((t2 <= t and q2 >= q and (t2 < t or q2 > q)) for (t2, q2, _) in pts))
table = page.split('<table class="configurations">')[1].split("</table>")[0]
marked = sorted(re.sub("<[^>]+>", "", "<td" + row.split("<td", 1)[1].split("</td>")[0]) for row in table.split("<tr")[2:] if 'class="front"' in row)
assert marked == front, (marked, front)
# the rays front is deterministic (rays and PSNR are the same bits on every run)
rpts = [(r["rays_traced_per_frame"], r["psnr"], l) for r, (_, _, l) in zip(rows, pts)]
rfront = sorted(l for (t, q, l) in rpts if not any((t2 <= t and q2 >= q and (t2 < t or q2 > q)) for (t2, q2, _) in rpts))
cells = lambda row: [re.sub("<[^>]+>", "", c) for c in ("<td" + row.split("<td", 1)[1]).split("</td>")]
rmarked = sorted(cells(row)[0] for row in table.split("<tr")[2:] if cells(row)[8] == "yes")
assert rmarked == rfront, (rmarked, rfront)
assert page.count("<svg") == 3 and 'id="report-ready">3 plots, 3 configurations, %d on the time front' % len(front) in page
for name in os.listdir(sys.argv[2] + "/plots"):
    assert name.endswith((".svg", ".png")), name
svgs = [n for n in os.listdir(sys.argv[2] + "/plots") if n.endswith(".svg")]
assert len(svgs) == 3, svgs
# the shared plotting module: ticks at round numbers (steps of 1, 2 or 5 times a power of ten on
# a linear axis, 1-2-5 or powers of ten on a log one), the last x label inside the picture, the
# y axis label left of every y tick label
def round_step(a, b):
    d = abs(b - a)
    e = 10.0 ** __import__("math").floor(__import__("math").log10(d))
    return any(abs(d - m * e) <= 1e-6 * d for m in (1, 2, 5, 10))
for name in svgs:
    svg = open(sys.argv[2] + "/plots/" + name).read()
    width = float(re.search(r'<svg[^>]* width="([0-9.]+)"', svg).group(1))
    for axis in ("x", "y"):
        ticks = re.findall(r'class="tick-%s" x="([0-9.]+)"[^>]*>([^<]*)<' % axis, svg)
        values = [float(t) for _, t in ticks]
        assert len(values) >= 2, (name, axis, values)
        log = all(v > 0 for v in values) and any(values[i + 1] / values[i] >= 2 - 1e-9 for i in range(len(values) - 1)) and not all(round_step(values[i], values[i + 1]) for i in range(len(values) - 1))
        for i in range(len(values) - 1):
            if log:
                r = values[i + 1] / values[i]
                assert any(abs(r - q) < 1e-6 for q in (2, 2.5, 10)), (name, axis, values)
            else:
                assert round_step(values[i], values[i + 1]), (name, axis, values)
        if axis == "x":
            x, text = float(ticks[-1][0]), ticks[-1][1]
            assert x + 3.25 * len(text) <= width + 0.5, (name, x, text, width)
        else:
            leftmost = min(float(x) - 6.5 * len(t) for x, t in ticks)
            assert leftmost >= 18, (name, leftmost)  # the rotated axis label is centred at x = 12
PYTHON
if command -v rsvg-convert >/dev/null; then
  checks=$((checks + 1))
  [ "$(ls "$TMP/report/plots"/*.png | wc -l)" -eq 3 ] || { echo "FAIL: PNG export"; failures=$((failures + 1)); }
fi
CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -n "$CHROMIUM" ]; then
  expect 0 "headless Chromium renders the report" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --dump-dom "file://$TMP/report/index.html"
  contains 'id="report-ready">3 plots, 3 configurations' "Chromium loaded the page"
  contains "Pareto front" "Chromium parsed the plots"
else
  echo "SKIPPED: headless Chromium check (chromium is not installed: apt-get install chromium)"
fi
# A synthetic result set whose times span four decades: the time axis turns logarithmic, with
# ticks at powers of ten; the front is the fast-and-bad, slow-and-good staircase.
mkdir -p "$TMP/synthetic"
"$PY" - "$TMP/synthetic/results.json" <<'PYTHON'
import json, sys
rows = []
for i, (s, q) in enumerate([(0.0004, 20.0), (0.003, 25.0), (0.02, 24.0), (0.3, 31.0), (2.5, 30.0)]):
    rows.append({"id": "m-%d" % i, "scene": "cornell", "mode": "m%d" % i, "params": {}, "width": 64,
                 "height": 36, "gaze": "centre", "frames": 1, "every": 1, "status": "done",
                 "psnr": q, "ssim": 0.5, "temporal_error": 0.01, "seconds_per_frame": s,
                 "rays_traced_per_frame": 1000.0 * (i + 1), "pixels_shaded_per_frame": 10.0,
                 "ring_outer_deg": [1, 2], "ring_psnr": [q, q], "ring_rmse": [0.1, 0.1],
                 "ring_ssim": [0.5, 0.5], "counters_per_frame": {}})
json.dump({"results": rows}, open(sys.argv[1], "w"))
PYTHON
expect 0 "report on synthetic results" -- "$FOVREF" sweep report "$TMP/synthetic" --html "$TMP/synthetic/html"
contains "3 on the time front" "front of the staircase"
"$PY" - "$TMP/synthetic/html/plots" <<'PYTHON' || { echo "FAIL: log time axis"; failures=$((failures + 1)); }
import os, re, sys
name = [n for n in os.listdir(sys.argv[1]) if n.endswith("-time.svg")][0]
svg = open(sys.argv[1] + "/" + name).read()
ticks = [float(t) for t in re.findall(r'class="tick-x"[^>]*>([^<]*)<', svg)]
assert ticks == [0.1, 1, 10, 100, 1000, 10000], ticks  # ms, powers of ten
PYTHON

expect 2 "report without results" -- "$FOVREF" sweep report "$TMP/a2" --html "$TMP/r2"
contains "run \`fovref sweep merge" "says to merge first"

# Resumable: a rerun skips every finished job (their results stay untouched); a removed result
# is recomputed, the others are not.
touch -d "2000-01-01" "$TMP/a/results"/*/job.json
first=$(ls "$TMP/a/results" | head -1)
rm -rf "$TMP/a/results/$first"
expect 0 "rerun" -- "$FOVREF" sweep run "$TMP/a" --jobs 2
checks=$((checks + 1))
stale=$(find "$TMP/a/results" -name job.json -newermt "2001-01-01" | wc -l)
if [ "$stale" -ne 1 ] || [ ! -f "$TMP/a/results/$first/job.json" ]; then
  echo "FAIL: rerun recomputed $stale job(s), expected only the removed one"; failures=$((failures + 1))
fi
expect 0 "one job alone" -- "$FOVREF" sweep job "$TMP/a" 1
contains "is done (skipped)" "finished job skipped"
expect 2 "index out of range" -- "$FOVREF" sweep job "$TMP/a" 99
contains "index 99 is not in the plan" "names the index"

# A failing job: the shared reference directory holds another reference (edited by hand). The
# run names the failed jobs and how to rerun one alone, exits 1, and leaves no partial result.
expect 0 "plan c" -- "$FOVREF" sweep plan "$TMP/sweep.json" "$TMP/c"
expect 0 "reference job" -- "$FOVREF" sweep job "$TMP/c" 0
"$PY" - "$TMP/c"/references/*/reference.json <<'PYTHON'
import json, sys
key = json.load(open(sys.argv[1])); key["width"] = 1; json.dump(key, open(sys.argv[1], "w"))
PYTHON
expect 1 "run with a broken reference" -- "$FOVREF" sweep run "$TMP/c" --jobs 2
contains "FAILED" "names the failures"
contains "rerun one alone to see why: fovref sweep job" "says how to see why"
expect 2 "the job alone says why" -- "$FOVREF" sweep job "$TMP/c" 1
contains "holds a reference for other settings" "the reason"
checks=$((checks + 1))
if [ -n "$(ls "$TMP/c/results" 2>/dev/null)" ]; then
  echo "FAIL: failed jobs left something in results/: $(ls "$TMP/c/results")"; failures=$((failures + 1))
fi

# The same sweep through GNU parallel (the export's job lists), then merged: the same results.
expect 0 "plan b" -- "$FOVREF" sweep plan "$TMP/sweep.json" "$TMP/b"
expect 0 "export parallel" -- "$FOVREF" sweep export "$TMP/b" --format parallel --fovref "$FOVREF"
check_file "$TMP/b/export/jobs.txt" "jobs.txt"
if command -v parallel >/dev/null; then
  expect 0 "GNU parallel runs the exported lists" -- sh "$TMP/b/export/run-parallel.sh"
  check_file "$TMP/b/export/jobs.log" "parallel's joblog"
  expect 0 "merge b" -- "$FOVREF" sweep merge "$TMP/b"
  checks=$((checks + 1))
  if ! cmp -s <(cut -d, -f1-14 "$TMP/a/results.csv") <(cut -d, -f1-14 "$TMP/b/results.csv"); then
    echo "FAIL: GNU parallel's results differ from sweep run's"; diff <(cut -d, -f1-14 "$TMP/a/results.csv") <(cut -d, -f1-14 "$TMP/b/results.csv") | head
    failures=$((failures + 1))
  fi
else
  echo "SKIPPED: GNU parallel run (not installed: apt-get install parallel)"
fi
expect 0 "export slurm" -- "$FOVREF" sweep export "$TMP/b" --format slurm
check_file "$TMP/b/export/jobs.sbatch" "Slurm script"
checks=$((checks + 1))
grep -q -- "--array=0-2" "$TMP/b/export/jobs.sbatch" && grep -q 'SLURM_ARRAY_TASK_ID + 1' "$TMP/b/export/jobs.sbatch" \
  && grep -q -- "--dependency=afterok" "$TMP/b/export/submit-slurm.sh" || { echo "FAIL: Slurm array script"; failures=$((failures + 1)); }
expect 0 "export k8s" -- "$FOVREF" sweep export "$TMP/b" --format k8s --image registry/fovref:1
checks=$((checks + 1))
grep -q "completionMode: Indexed" "$TMP/b/export/k8s-jobs.yaml" && grep -q "completions: 3" "$TMP/b/export/k8s-jobs.yaml" \
  && grep -q 'JOB_COMPLETION_INDEX + 1' "$TMP/b/export/k8s-jobs.yaml" && grep -q "image: registry/fovref:1" "$TMP/b/export/k8s-jobs.yaml" \
  || { echo "FAIL: Kubernetes Indexed Job manifest"; failures=$((failures + 1)); }
if "$PY" -c "import yaml" 2>/dev/null; then
  expect 0 "the manifest is YAML" -- "$PY" -c "import sys, yaml; d = yaml.safe_load(open(sys.argv[1])); assert d['spec']['completionMode'] == 'Indexed'" "$TMP/b/export/k8s-jobs.yaml"
fi
expect 2 "unknown export format" -- "$FOVREF" sweep export "$TMP/b" --format pbs

# Bad sweep files: a clear message with the file, the line and the JSON pointer; no plan written.
bad() {  # bad NAME JSON EXPECTED-TEXT
  printf '%s\n' "$2" > "$TMP/$1.json"
  expect 2 "bad sweep file: $1" -- "$FOVREF" sweep plan "$TMP/$1.json" "$TMP/bad-$1"
  contains "$3" "$1: message"
  checks=$((checks + 1))
  if [ -e "$TMP/bad-$1/plan.json" ]; then echo "FAIL: $1: a plan was written"; failures=$((failures + 1)); fi
}
bad missing-scenes '{"configurations": [{"mode": "basic"}]}' "'scenes' is required"
bad unknown-mode '{"scenes": ["cornell"],
 "configurations": [{"mode": "bsaic"}]}' "unknown-mode.json:2: /configurations/0/mode: unknown mode"
bad unknown-param '{"scenes": ["cornell"], "configurations": [{"mode": "fov",
  "grid": {"sigmaa": [1]}}]}' "/configurations/0/grid/sigmaa: mode 'fov' has no parameter 'sigmaa'"
bad empty-grid '{"scenes": ["cornell"], "configurations": [{"mode": "fov", "grid": {"sigma": []}}]}' "expected a non-empty array of values"
bad resolution '{"scenes": ["cornell"], "resolutions": ["64by36"], "configurations": [{"mode": "basic"}]}' "a resolution is WxH"
bad scene '{"scenes": ["no-such-scene"], "configurations": [{"mode": "basic"}]}' "/scenes/0"
bad unknown-key '{"scenes": ["cornell"], "configurations": [{"mode": "basic"}], "frame": 3}' "/frame: unknown key"
bad syntax '{"scenes": ["cornell"],, }' "JSON syntax error"
bad value '{"scenes": ["cornell"], "configurations": [{"mode": "fov", "params": {"sigma": "1:2"}}]}' "may not be empty or hold"
bad repeat '{"scenes": ["cornell"], "configurations": [{"mode": "fov", "grid": {"sigma": [1.5, 1.5]}}]}' "two configurations give the same job"
expect 2 "missing sweep file" -- "$FOVREF" sweep plan "$TMP/nope.json" "$TMP/nope"
contains "nope.json" "names the file"
expect 2 "run without a plan" -- "$FOVREF" sweep run "$TMP/nothing"
contains "sweep plan FILE" "says what to do"
finish
