#!/usr/bin/env python3
"""Flash and RAM use of a PIC18 program from its gplink map file, checked
against the part's limits (PIC18F2550: 32 KB flash, 2 KB RAM).

  flash = program-memory sections below the end of flash (code, romdata:
          code, constants, initial values of initialised data); the
          configuration words at 0x300000 are not counted
  RAM   = data sections below the SFR area (udata, idata: variables,
          SDCC's temporaries, the 256-byte software stack)

Usage: pic-size.py MAP_FILE [--name NAME] [--flash BYTES] [--ram BYTES]
                   [--sfr-start ADDR] [--report FILE] [--json FILE --servos N]
                   [--remove-on-fail HEX]
Prints one line (also written to --report FILE; --json FILE writes the same
figures and the build's servo outputs for the simulator's PIC module
process); exit status 1 when a limit is exceeded (or the map file has no
section table; --remove-on-fail then deletes HEX so that a stale file cannot
be used), 0 otherwise.
"""
import argparse
import json
import os
import re
import sys

ROW_RE = re.compile(
    r"^\s*(\S+)\s+(code|romdata|udata|idata|udata_acs|idata_acs|udata_ovr|udata_shr|"
    r"access_ovr|\S+)\s+0x([0-9a-fA-F]+)\s+(program|data)\s+0x([0-9a-fA-F]+)\s*$")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("map")
    ap.add_argument("--name", default=None)
    ap.add_argument("--flash", type=int, default=32768)
    ap.add_argument("--ram", type=int, default=2048)
    ap.add_argument("--sfr-start", type=lambda s: int(s, 0), default=0xF60)
    ap.add_argument("--stack-section", default="stack_section")
    ap.add_argument("--report", default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--servos", type=int, default=None)
    ap.add_argument("--remove-on-fail", default=None)
    a = ap.parse_args()

    flash = ram = stack = 0
    rows = 0
    in_sections = False
    with open(a.map, encoding="latin-1") as f:
        for line in f:
            if "Section Info" in line:
                in_sections = True
                continue
            if in_sections and ("Program Memory Usage" in line or "Symbols" in line):
                break
            if not in_sections:
                continue
            m = ROW_RE.match(line)
            if not m:
                continue
            name, _typ, addr, loc, size = m.groups()
            addr, size = int(addr, 16), int(size, 16)
            rows += 1
            if loc == "program":
                if addr < a.flash:
                    flash += size
            elif addr < a.sfr_start:
                ram += size
                if name == a.stack_section:
                    stack += size
    name = a.name or a.map
    over = []
    if rows == 0:
        line = "%s: no section table in %s" % (name, a.map)
        over.append("map")
    else:
        if flash > a.flash:
            over.append("flash")
        if ram > a.ram:
            over.append("RAM")
        line = ("%s: flash %d / %d bytes (%.1f%%), RAM %d / %d bytes (%.1f%%, %d of it stack)%s"
                % (name, flash, a.flash, 100.0 * flash / a.flash, ram, a.ram,
                   100.0 * ram / a.ram, stack,
                   "  OVER THE LIMIT: " + ", ".join(over) if over else ""))
    print(line)
    if a.report:
        with open(a.report, "w") as f:
            f.write(line + "\n")
    if a.json and not over:
        with open(a.json, "w") as f:
            json.dump({"flash_bytes": flash, "flash_total": a.flash, "ram_bytes": ram,
                       "ram_total": a.ram, "stack_bytes": stack, "servos": a.servos}, f)
            f.write("\n")
    if over and a.remove_on_fail:
        try:
            os.remove(a.remove_on_fail)
        except OSError:
            pass
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
