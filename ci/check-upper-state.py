#!/usr/bin/env python3
"""Checks that no AVX code in a binary hands dirty upper register halves to SSE code.

A function that uses ymm or zmm registers (the [[gnu::target("avx...")]] lanes of the SDF
and DEM kernels) must execute vzeroupper before each `ret` and before each `call` of code
that is not itself AVX: Intel cores run every legacy-SSE instruction after it with a merge of
the dirty upper halves, which made the whole DEM step about 10 % slower there
(docs/portability.md "Upper register state"). GCC inserts vzeroupper itself but once left it
out before a call and a return.

Usage: check-upper-state.py BINARY   (objdump from binutils; exit 1 with the offenders listed)
       check-upper-state.py --self-test   (the checker on the offending code it was made for)

For each `ret` and `call` in such a function the instructions before it are scanned backwards
in address order: a vzeroupper first is fine; a ymm/zmm instruction first, or the function's
start, or the end of another block (an unconditional jmp or a ret: the code is reached by a
jump, which this scan does not follow) is reported. Calls of the errno path of sqrt (taken
only for a negative argument, whose result is NaN anyway) are not reported.
"""
import re
import subprocess
import sys

EXEMPT_CALLEES = ("sqrt@plt",)  # the math-errno path of sqrt: only for a negative argument


def disassembly(binary):
    return subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", binary], capture_output=True, text=True,
                          check=True).stdout


def functions(text):
    name, body = None, []
    for line in text.split("\n"):
        header = re.match(r"[0-9a-f]+ <(.*)>:$", line)
        if header:
            if name is not None:
                yield name, body
            name, body = header.group(1), []
        elif name is not None and re.match(r"\s+[0-9a-f]+:\t", line):
            body.append(line)
    if name is not None:
        yield name, body


def uses_wide(line):
    return re.search(r"%[yz]mm\d", line) is not None


def instruction(line):
    return line.split("\t", 1)[1].strip() if "\t" in line else ""


def offenders(text):
    """The calls and returns of AVX functions in objdump's text without vzeroupper before them."""
    wide_functions = {}
    for name, body in functions(text):
        if any(uses_wide(line) for line in body):
            wide_functions[name] = body
    found = []
    for name, body in wide_functions.items():
        for k, line in enumerate(body):
            op = instruction(line)
            is_ret = re.match(r"ret", op) is not None
            call = re.match(r"call\s+[0-9a-f]+ <(.*)>", op)
            if not is_ret and not call:
                continue
            if call and (call.group(1) in wide_functions or call.group(1).endswith(EXEMPT_CALLEES)):
                continue
            verdict = "the function's start"
            for back in range(k - 1, -1, -1):
                prev = instruction(body[back])
                if prev.startswith("vzeroupper"):
                    verdict = None
                    break
                if uses_wide(body[back]):
                    verdict = "a ymm/zmm instruction: " + prev
                    break
                if re.match(r"(jmp|ret)\b", prev):
                    verdict = "a jump target (after: " + prev + ")"
                    break
            if verdict:
                found.append(f"{name}\n    {op} at {line.split(':')[0].strip()}: no vzeroupper since {verdict}")
    return found, len(wide_functions)


# The drift of 5dc074a (GCC 12), shortened: a call of SSE code and a return, both dirty; then the
# same function with vzeroupper before its return and without the call, and an SSE function.
SELF_TEST_BAD = """
0000000000573090 <kicks_and_drifts_avx512(FastState&, unsigned long, unsigned long)>:
  5733a0:\tvextractf128 $0x1,%ymm1,%xmm0
  5733a6:\tcmp    %rdx,%r8
  5733b7:\tcall   572e50 <kicks_and_drifts_one_by_one(FastState&, unsigned long, unsigned long, bool)>
  5733bc:\tleave
  5733c6:\tret
"""
SELF_TEST_GOOD = """
0000000000573090 <kicks_and_drifts_avx512(FastState&, unsigned long, unsigned long, double&)>:
  5733a0:\tvextractf128 $0x1,%ymm1,%xmm0
  5733a6:\tvzeroupper
  5733bc:\tleave
  5733c6:\tret
0000000000572e50 <kicks_and_drifts_one_by_one(FastState&, unsigned long, unsigned long, bool)>:
  572e50:\tmovupd (%rdx),%xmm5
  572e58:\tret
"""


def self_test():
    bad, _ = offenders(SELF_TEST_BAD)
    good, wide = offenders(SELF_TEST_GOOD)
    ok = len(bad) == 2 and "call" in bad[0] and "ret" in bad[1] and not good and wide == 1
    print("self-test:", "passed" if ok else f"FAILED: bad {bad}, good {good}, wide {wide}")
    return 0 if ok else 1


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    found, wide = offenders(disassembly(sys.argv[1]))
    if found:
        print(f"{sys.argv[1]}: {len(found)} call(s)/return(s) of AVX code may leave the upper halves dirty:")
        print("\n".join(found))
        return 1
    print(f"{sys.argv[1]}: {wide} AVX function(s), every call and return after vzeroupper")
    return 0


if __name__ == "__main__":
    sys.exit(main())
