#!/usr/bin/env python3
"""Calls from AVX code into legacy-SSE code without a vzeroupper before them.

A function that writes ymm registers and then calls a function compiled without AVX (whose
instructions use the legacy SSE encoding: `mulss`, not `vmulss`) should clear the upper halves
first (vzeroupper; avx::leave_for_scalar in ref/core/avx_lanes.h). Otherwise, on Intel cores,
every SSE instruction of the callee carries a false dependency on the dirty upper halves: the
scalar fallback lanes of pow_fast_array ran about 5x slower on an Intel Xeon until this was fixed
(docs/speed.md). g++ inserts vzeroupper itself before most such calls, but not all.

The check reads `objdump -d` of a binary. In each function that names a ymm or zmm register, a
call is reported when some ymm instruction reaches it without a vzeroupper in between: earlier in
the function, or later inside a loop (a backward jump) that holds the call. Only callees that
themselves hold legacy-SSE instructions are reported (a callee compiled for AVX costs nothing).

  check_vzeroupper.py BINARY       check a linked binary (g++ -O2; the release build's ctest)
  check_vzeroupper.py --self-test  prove the check reports a call it should and passes a guarded one
"""
import re
import subprocess
import sys

HEADER = re.compile(r"^([0-9a-f]+) <(.*)>:$")
WIDE = re.compile(r"%[yz]mm")
JUMP = re.compile(r"^j\w*\s+([0-9a-f]+)")
CALL = re.compile(r"^call\w*\s+([0-9a-f]+)\s+<(.*)>")
# a legacy-SSE instruction: an xmm operand and a mnemonic without the VEX/EVEX 'v' prefix
LEGACY = re.compile(r"^(?!v)[a-z0-9]+\s.*%xmm")


def parse(text):
    """{name: (start address, [(address, instruction)])} of `objdump -d --no-show-raw-insn -C`."""
    functions, current = {}, None
    for line in text.splitlines():
        m = HEADER.match(line)
        if m:
            current = m.group(2)
            functions[current] = (int(m.group(1), 16), [])
            continue
        if current is None or "\t" not in line:
            continue
        address = int(line.split(":", 1)[0].strip(), 16)
        functions[current][1].append((address, line.split("\t", 1)[1].strip()))
    return functions


def unguarded_calls(functions):
    """[(caller, callee)] of the calls the docstring describes."""
    legacy = {start for start, body in functions.values() if any(LEGACY.match(i) for _, i in body)}
    found = []
    for name, (_, body) in functions.items():
        wide = [k for k, (_, i) in enumerate(body) if WIDE.search(i) and "vzeroupper" not in i]
        if not wide:
            continue
        clean = [k for k, (_, i) in enumerate(body) if "vzeroupper" in i]
        index = {address: k for k, (address, _) in enumerate(body)}
        loops = []  # (first, last) instruction of each backward jump's span
        for k, (address, i) in enumerate(body):
            m = JUMP.match(i)
            if m and int(m.group(1), 16) < address and int(m.group(1), 16) in index:
                loops.append((index[int(m.group(1), 16)], k))

        def cleared(a, b):  # a vzeroupper at an index in [a, b)
            return any(a <= c < b for c in clean)

        for k, (_, i) in enumerate(body):
            m = CALL.match(i)
            if not m or int(m.group(1), 16) not in legacy:
                continue
            before = [w for w in wide if w < k]
            dirty = bool(before) and not cleared(before[-1], k)
            for first, last in loops:
                after = [w for w in wide if k < w <= last]
                if first <= k <= last and after and not cleared(after[-1], last + 1) \
                        and not cleared(first, k):
                    dirty = True
            if dirty:
                found.append((name, m.group(2)))
    return sorted(set(found))


SELF_TEST = """
0000000000001000 <scalar(float)>:
    1000:\tmulss  %xmm0,%xmm0
    1004:\tret
0000000000001010 <vector_only(float)>:
    1010:\tvmulss %xmm0,%xmm0,%xmm0
    1014:\tret
0000000000001020 <unguarded(float const*)>:
    1020:\tvmovups (%rdi),%ymm0
    1024:\tcall   1000 <scalar(float)>
    1028:\tcall   1010 <vector_only(float)>
    102c:\tret
0000000000001030 <guarded(float const*)>:
    1030:\tvmovups (%rdi),%ymm0
    1034:\tvzeroupper
    1038:\tcall   1000 <scalar(float)>
    103c:\tret
0000000000001040 <in_a_loop(float const*)>:
    1040:\tcall   1000 <scalar(float)>
    1044:\tvmovups (%rdi),%ymm0
    1048:\tjne    1040 <in_a_loop(float const*)>
    104c:\tret
"""


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        found = unguarded_calls(parse(SELF_TEST))
        expected = [("in_a_loop(float const*)", "scalar(float)"),
                    ("unguarded(float const*)", "scalar(float)")]
        if found != expected:
            print(f"self-test FAILED: reported {found}, expected {expected}")
            return 1
        print("self-test passed: unguarded calls (straight and in a loop) are reported, "
              "a guarded call and a call into AVX code are not")
        return 0
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", sys.argv[1]], check=True,
                          capture_output=True, text=True).stdout
    functions = parse(text)
    found = unguarded_calls(functions)
    for caller, callee in found:
        print(f"no vzeroupper before a call into SSE code: {caller}\n    -> {callee}")
    if found:
        print("clear the upper halves first: avx::leave_for_scalar() (ref/core/avx_lanes.h)")
        return 1
    print(f"check_vzeroupper: {len(functions)} functions, no unguarded call from AVX into SSE code")
    return 0


if __name__ == "__main__":
    sys.exit(main())
