#!/usr/bin/env python3
"""Runs `fovref probe --debugger gdb --json`'s render under gdb in batch mode and checks each stop.

usage: gdb_stops.py PROBE_JSON WORKDIR [LOG]

From the probe's JSON (its breakpoints: function, condition, stage index, coordinates), writes a
gdb script that sets every breakpoint with a command list printing where it stopped (the frame
line: function, arguments, file:line) and the coordinates, frame, stage and eye the program holds
there, then runs the printed command's program under `gdb -batch`. Checks: every breakpoint stops
at least once; every stop is in its named function, with a source line, at coordinates among the
breakpoint's points, in the probed frame and in the breakpoint's stage (and eye). Exits 1 with the
reasons otherwise. LOG, when given, receives gdb's whole output.
"""
import json
import re
import shlex
import subprocess
import sys


def main():
    probe = json.load(open(sys.argv[1]))
    workdir = sys.argv[2]
    command = shlex.split(probe["debugger_command"])
    program_args = command[command.index("--args") + 1:]
    breakpoints = [b for b in probe["breakpoints"] if b["condition"]]
    script = ["set pagination off", "set confirm off", "set print frame-arguments scalars"]
    for k, b in enumerate(breakpoints):
        xn, yn = b["parameters"]
        script += [f"break {b['function']} if {b['condition']}", "commands", "silent", "frame",
                   f'printf "FOVREF-STOP {k} %d %d %d %d %d\\n", {xn}, {yn}, '
                   "fovref::debugger_position.frame, fovref::debugger_position.stage, "
                   "fovref::debugger_position.eye", "continue", "end"]
    script.append("run")
    with open(f"{workdir}/stops.gdb", "w") as f:
        f.write("\n".join(script) + "\n")
    run = subprocess.run(["gdb", "-q", "-batch", "-x", f"{workdir}/stops.gdb", "--args"] +
                         program_args, capture_output=True, text=True, timeout=900)
    out = run.stdout + run.stderr
    if len(sys.argv) > 3:
        with open(sys.argv[3], "w") as f:
            f.write(out)
    problems, hits, frame_line = [], [0] * len(breakpoints), None
    for line in out.splitlines():
        if line.startswith("#0"):
            frame_line = line
            continue
        m = re.match(r"FOVREF-STOP (\d+) (-?\d+) (-?\d+) (-?\d+) (-?\d+) (-?\d+)", line)
        if not m:
            if "Error in testing" in line or "No symbol" in line:
                problems.append(line)
            continue
        k, x, y, frame, stage, eye = map(int, m.groups())
        b = breakpoints[k]
        hits[k] += 1
        where = f"stop {hits[k]} of {b['function']}"
        located = re.match(r"#0\s+(?:0x[0-9a-f]+ in )?(\S+) \(.*\) at (\S+):(\d+)", frame_line or "")
        if not located:
            problems.append(f"{where}: no function and source line in '{frame_line}'")
        elif located.group(1) != b["function"]:
            problems.append(f"{where}: stopped in {located.group(1)}")
        if [x, y] not in b["points"]:
            problems.append(f"{where}: at ({x}, {y}), expected one of {b['points']}")
        if frame != probe["frame"] or stage != b["stage_index"]:
            problems.append(f"{where}: frame {frame} stage {stage}, expected frame "
                            f"{probe['frame']} stage {b['stage_index']}")
        if b["eye"] >= 0 and eye != b["eye"]:
            problems.append(f"{where}: eye {eye}, expected {b['eye']}")
        frame_line = None
    for k, b in enumerate(breakpoints):
        if hits[k] == 0:
            problems.append(f"{b['function']} ({b['coordinates']}) never stopped")
    if run.returncode != 0 or problems or not breakpoints:
        print(f"gdb exit {run.returncode}; {len(breakpoints)} breakpoints")
        print("\n".join(problems[:20]))
        print("\n".join(out.splitlines()[-15:]))
        sys.exit(1)
    print(f"{sum(hits)} stops in {len(breakpoints)} functions, each at its coordinates, frame "
          f"{probe['frame']}, stage and source line: " +
          ", ".join(f"{b['function'].split('::')[-1]} x{hits[k]}" for k, b in enumerate(breakpoints)))


if __name__ == "__main__":
    main()
