#!/usr/bin/env python3
"""SDCC for the PIC18 with its 8-bit truths made errors.

Runs the SDCC command after `--` and passes its output through. Warnings
that say the code means something else on an 8-bit part than on a PC fail
the compile (exit 1), each named, with what it means on the board:

   94  comparison is always false due to limited range of data type
  116  left shifting more than size of object changed to zero
  158  overflow in implicit constant conversion
  165  integer overflow in expression

Used by chainsim_pic_program() with STRICT (CMake option CHAINSIM_PIC_STRICT
of the chainsim package; docs/pic-in-the-loop.md).

Usage: pic-cc.py -- SDCC ARGS...
"""
import re
import subprocess
import sys

TRUTHS = {
    "94": "a comparison that a narrow type can never make true",
    "116": "a shift done in 16-bit int (int is 16 bits on the PIC18): its bits are lost",
    "158": "a constant that does not fit the type it is stored in",
    "165": "arithmetic on int constants that overflows 16 bits (int is 16 bits on the PIC18)",
}
WARNING_RE = re.compile(r"^(?P<where>.*?:\d+): warning (?P<num>\d+): (?P<text>.*)$")


def main():
    if "--" not in sys.argv:
        print(__doc__.splitlines()[-1], file=sys.stderr)
        return 2
    cmd = sys.argv[sys.argv.index("--") + 1:]
    r = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
    sys.stdout.write(r.stdout)
    sys.stderr.write(r.stderr)
    if r.returncode != 0:
        return r.returncode
    found = []
    for line in (r.stdout + r.stderr).splitlines():
        m = WARNING_RE.match(line.strip())
        if m and m.group("num") in TRUTHS:
            found.append("%s: error (8-bit truth, warning %s): %s: %s"
                         % (m.group("where"), m.group("num"), m.group("text"), TRUTHS[m.group("num")]))
    if found:
        sys.stderr.write("\n".join(found) + "\n")
        sys.stderr.write("pic-cc: %d warning(s) that mean the board computes something else than a PC "
                         "(the PIC build's STRICT option makes them errors)\n" % len(found))
        # the object is not to be linked
        for i, a in enumerate(cmd):
            if a == "-o" and i + 1 < len(cmd):
                try:
                    import os
                    os.remove(cmd[i + 1])
                except OSError:
                    pass
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
