#!/usr/bin/env python3
"""gplink for a chainsim PIC program, its RAM failures told in words.

Runs the gplink command after `--`. When it fails to place a data section
(gplink: "Relocation of section ... failed", "no definition that matches the
type of section ...", "no target memory available for section ..."), looks
the section up in the program's SDCC assembly (--asm-dir) and says which
variables it holds, how big they are, and why the PIC18F2550 cannot place
them: RAM comes in 256-byte banks, and SDCC keeps every function's locals in
static RAM, so one variable over a bank (or a function's locals that fill
one) cannot be linked.

Usage: pic-link.py --asm-dir DIR -- GPLINK ARGS...
"""
import argparse
import glob
import os
import re
import subprocess
import sys

SECTION_RE = re.compile(r'section "([^"]+)"')
BANK = 256


def section_contents(asm_dir, section):
    """(asm file, C file, [(symbol, bytes)]) of the section, or None"""
    for path in sorted(glob.glob(os.path.join(asm_dir, "*.asm"))):
        with open(path, errors="replace") as f:
            lines = f.read().splitlines()
        for i, line in enumerate(lines):
            if re.match(r"^%s\s+udata\b" % re.escape(section), line):
                syms = []
                for l in lines[i + 1:]:
                    m = re.match(r"^(\S+)\s+res\s+(\d+)", l)
                    if not m:
                        break
                    syms.append((m.group(1), int(m.group(2))))
                c_file = None
                for l in lines:
                    m = re.match(r"^;\t\.line\t\d+; (\S+)", l)
                    if m:
                        c_file = m.group(1)
                        break
                return path, c_file, syms
    return None


def describe(symbol):
    """SDCC names a local `_<function>_<variable>_<level>_<n>`"""
    m = re.match(r"^_(.+)_\d+_\d+$", symbol)
    return ("local variable %s (SDCC's function_variable)" % m.group(1)) if m else ("variable %s" % symbol.lstrip("_"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--asm-dir", required=True)
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd and a.cmd[0] == "--" else a.cmd
    r = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
    sys.stdout.write(r.stdout)
    sys.stderr.write(r.stderr)
    if r.returncode == 0:
        return 0
    out = r.stdout + r.stderr
    told = set()
    for name in SECTION_RE.findall(out):
        if name in told:
            continue
        told.add(name)
        found = section_contents(a.asm_dir, name)
        if not found:
            continue
        path, c_file, syms = found
        total = sum(n for _, n in syms)
        where = c_file or os.path.basename(path)
        what = ", ".join("%s: %d bytes" % (describe(s), n) for s, n in syms) or "no variables"
        sys.stderr.write(
            "pic-link: the RAM section %s of %s holds %d bytes (%s). The PIC18F2550's RAM comes in %d-byte "
            "banks and gplink places a section within one bank; SDCC keeps every function's locals in "
            "static RAM, so %s. Make the variable smaller, split it, or keep it in flash (const) if it does "
            "not change.\n"
            % (name, where, total, what, BANK,
               "a variable of more than %d bytes cannot be placed at all" % BANK if total > BANK
               else "no bank had %d bytes left for it" % total))
    return r.returncode


if __name__ == "__main__":
    sys.exit(main())
