#!/usr/bin/env python3
"""Firmware-in-the-loop tests of the PIC18F2550 build in gpsim.

Builds the firmware with tools/pic-build.sh (the toolchain must have been
built before: otherwise the test is SKIPPED, exit code 77, with the reason),
loads a program's .cod/.hex into gpsim and drives its pins from a generated
gpsim command file:

  build     - only the build: every program fits the part (the build fails
              when one is over 32 KB flash / 2 KB RAM), and hal-pic/README.md's
              memory table is what the build measured
  rotation  - the servo pulses after reset (hold straight: 1.5 ms every 20 ms
              on RB2 and RB3); discovery over I2C (ENUM_OFFER by general call
              while Sin is high -> ENUM_REPLY to the central control's address
              0x10, Sout raised); SET_GAIT + START -> the pitch servo's pulse
              follows the set-point (A sin(k phase), omega = 0: a constant);
              STATUS -> STATUS_REPLY; a second SET_GAIT beyond the servo's
              range -> the yaw pulse clamps at 1.0 ms.
  central   - after reset the central control raises Sout and offers address
              0x20 by general call; with nobody on the bus it logs the
              "no reply" and "chain: (0 modules)" lines on its UART (read
              from the TXREG writes).

The test's I2C master is bit-banged: gpsim pull-up modules on SDA and SCL
whose voltage/resistance the command file switches at given cycles (5 V
through 10 kOhm = released, 0 V through 100 Ohm = driven low), so the lines
are open-drain as on the real bus. gpsim's i2c2par module is the central
control (slave 0x10) that acknowledges the module's replies; its 8-bit port
shows the last data byte it received. Servo pulses, Sout and the bytes the
firmware sends are read from gpsim's register-write log (LATB, LATC, SSPBUF,
TXREG) with their cycle numbers (0.2 us each).

Usage: gpsim_test.py {build,rotation,central} --repo DIR --build-dir DIR [--keep]
"""
import argparse
import fcntl
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = 77
FCY = 5_000_000          # instruction cycles per second (20 MHz crystal / 4)
CYC_PER_MS = FCY // 1000
CYC_PER_US = FCY // 1_000_000

# the chain command set, read from firmware/common/chain_commands.h (main())
CC = {}

LATB, LATC, SSPBUF, TXREG = 0x0F8A, 0x0F8B, 0x0FC9, 0x0FAD


def skip(reason):
    print("SKIP: " + reason)
    sys.exit(SKIP)


def i16(v):
    v &= 0xFFFF
    return [v & 0xFF, v >> 8]


def load_commands(repo):
    """the integer #defines of chain_commands.h (codes, lengths, offsets)"""
    path = os.path.join(repo, "firmware", "common", "chain_commands.h")
    with open(path) as f:
        for m in re.finditer(r"^#define\s+(\w+)\s+\(?(0x[0-9A-Fa-f]+|\d+)[uUlL]*\)?\s*(?:/\*.*)?$",
                             f.read(), re.M):
            CC[m.group(1)] = int(m.group(2), 0)


def set_gait(gait, amp, omega, phase, axis):
    """a SET_GAIT frame as the header lays it out (fields it adds later, such
    as the posture, stay 0)"""
    f = [0] * CC["CC_SET_GAIT_LEN"]
    f[0] = CC["CC_SET_GAIT"]
    f[CC["CC_GAIT_OFF_GAIT"]] = gait
    for off, v in (("CC_GAIT_OFF_AMP", amp), ("CC_GAIT_OFF_OMEGA", omega),
                   ("CC_GAIT_OFF_PHASE", phase)):
        f[CC[off]:CC[off] + 2] = i16(v)
    f[CC["CC_GAIT_OFF_AXIS"]] = axis
    return f


# ---- toolchain and build ---------------------------------------------------------

def build(repo, build_dir):
    """Build the hex files (under a lock: the tests may run in parallel)."""
    cache = subprocess.run([os.path.join(repo, "tools", "pic-toolchain.sh"), "--print-cache"],
                           capture_output=True, text=True, check=True).stdout.strip()
    for stamp in ("compiler", "runtime"):
        if not os.path.isfile(os.path.join(cache, "stamps", stamp)):
            skip("the PIC toolchain is not built in %s (run tools/pic-build.sh; "
                 "CI does)" % cache)
    os.makedirs(build_dir, exist_ok=True)
    with open(os.path.join(build_dir, ".gpsim-test.lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        r = subprocess.run([os.path.join(repo, "tools", "pic-build.sh"), build_dir],
                           capture_output=True, text=True)
    if r.returncode != 0:
        sys.stdout.write(r.stdout[-4000:])
        sys.stdout.write(r.stderr[-4000:])
        print("FAIL: tools/pic-build.sh failed")
        sys.exit(1)
    summary = r.stdout.split("[pic-build] PIC18F2550 programs:")[-1]
    for line in summary.splitlines():
        if ".hex: flash" in line:
            print("build: " + line.strip())


# ---- gpsim command file -----------------------------------------------------------

class Script:
    """Actions at given cycles, turned into 'break c N' / 'run' steps."""

    def __init__(self):
        self.head = []
        self.events = {}  # cycle -> [commands]

    def at(self, cycle, *cmds):
        self.events.setdefault(int(cycle), []).extend(cmds)

    def text(self, end_cycle):
        out = list(self.head)
        for c in sorted(self.events):
            out.append("break c %d" % c)
            out.append("run")
            out.extend(self.events[c])
        out.append("break c %d" % end_cycle)
        out.append("run")
        out.append("quit")
        return "\n".join(out) + "\n"


class Bus:
    """A bit-banged I2C master on the pull-up modules pu_sda / pu_scl."""

    HALF = 5 * CYC_PER_US         # 5 us: 100 kHz
    QUART = HALF // 2
    BYTE_GAP = 200 * CYC_PER_US   # the slave stretches SCL until its ISR runs

    def __init__(self, script):
        self.s = script

    def _line(self, t, name, low):
        if low:
            self.s.at(t, "pu_%s.voltage = 0.0" % name, "pu_%s.resistance = 100.0" % name)
        else:
            self.s.at(t, "pu_%s.resistance = 10000.0" % name, "pu_%s.voltage = 5.0" % name)

    def frame(self, t, addr7, data):
        """START, address + write, data, STOP from cycle t; returns the end."""
        h, q = self.HALF, self.QUART
        self._line(t, "sda", True)             # start: SDA falls while SCL is high
        t += h
        self._line(t, "scl", True)
        t += h
        for byte in [addr7 << 1] + list(data):
            for i in range(7, -1, -1):
                self._line(t, "sda", not (byte >> i) & 1)
                self._line(t + q, "scl", False)
                self._line(t + q + h, "scl", True)
                t += 2 * h
            self._line(t, "sda", False)        # release SDA: the slave acknowledges
            self._line(t + q, "scl", False)
            self._line(t + q + h, "scl", True)
            t += 2 * h + self.BYTE_GAP
        self._line(t, "sda", True)             # stop: SDA rises while SCL is high
        self._line(t + q, "scl", False)
        self._line(t + q + h, "sda", False)
        return t + q + h + h


def common_head(logfile, extra=()):
    return [
        "frequency %d" % (FCY * 4),
        "module library libgpsim_modules",
        "module load pullup pu_sda",
        "module load pullup pu_scl",
        "module load pullup pu_sin",
        "pu_sda.resistance = 10000.0",
        "pu_scl.resistance = 10000.0",
        "node sda",
        "attach sda portb0 pu_sda.pin",
        "node scl",
        "attach scl portb1 pu_scl.pin",
        "node sin",
        "attach sin portc4 pu_sin.pin",
    ] + list(extra) + [
        "log on %s" % logfile,
        "log w latb",
        "log w latc",
        "log w sspbuf",
        "log w txreg",
    ]


def run_gpsim(cod, script_text, workdir, timeout=300):
    stc = os.path.join(workdir, "test.stc")
    with open(stc, "w") as f:
        f.write(script_text)
    # -S disable: no source listing. gpsim 0.31 reads the source file of the
    # last instruction at every break, by the name stored in the .cod, which
    # holds at most 63 characters: a build directory with a long path leaves
    # a truncated name that can be a directory, and gpsim then crashes
    # (SIGSEGV in FileContext::ReadLine).
    r = subprocess.run(["gpsim", "-S", "disable", "-s", cod, "-i", "-c", stc],
                       stdin=subprocess.DEVNULL,
                       capture_output=True, text=True, timeout=timeout, cwd=workdir)
    with open(os.path.join(workdir, "gpsim.out"), "w") as f:
        f.write(r.stdout)
        f.write(r.stderr)
    if r.returncode != 0:
        print("FAIL: gpsim exited with status %d (output in %s/gpsim.out)" % (r.returncode, workdir))
        sys.exit(1)
    if "ERROR" in r.stdout or "ERROR" in r.stderr:
        errs = [l for l in (r.stdout + r.stderr).splitlines() if "ERROR" in l]
        print("FAIL: gpsim reported errors in the command file:\n  " + "\n  ".join(errs[:5]))
        sys.exit(1)
    return r.stdout


def parse_writes(logfile):
    """[(cycle, address, value)] of the logged register writes."""
    head_re = re.compile(r"^0x([0-9A-Fa-f]+)\s+p18f2550\s")
    wrote_re = re.compile(r"Wrote: 0x([0-9A-Fa-f]+) to \S+\(0x([0-9A-Fa-f]+)\)")
    writes = []
    cycle = None
    with open(logfile, encoding="latin-1") as f:
        for line in f:
            m = head_re.match(line)
            if m:
                cycle = int(m.group(1), 16)
                continue
            m = wrote_re.search(line)
            if m and cycle is not None:
                addr = int(m.group(2), 16)
                if addr in (LATB, LATC, SSPBUF, TXREG):
                    writes.append((cycle, addr, int(m.group(1), 16)))
    return writes


def pin_pulses(writes, addr, bit):
    """[(rise_cycle, fall_cycle)] of a port bit from the write log."""
    pulses, level, rise = [], 0, None
    for cyc, a, v in writes:
        if a != addr:
            continue
        new = (v >> bit) & 1
        if new and not level:
            rise = cyc
        elif level and not new and rise is not None:
            pulses.append((rise, cyc))
        level = new
    return pulses


def first_rise(writes, addr, bit):
    level = 0
    for cyc, a, v in writes:
        if a == addr:
            new = (v >> bit) & 1
            if new and not level:
                return cyc
            level = new
    return None


def sspbuf_bytes(writes, t0, t1):
    return [v for c, a, v in writes if a == SSPBUF and t0 <= c < t1]


class Checks:
    def __init__(self):
        self.failed = 0

    def check(self, ok, what):
        print("%s: %s" % ("PASS" if ok else "FAIL", what))
        if not ok:
            self.failed += 1


def check_pulses(ck, writes, name, bit, t0, t1, want_us):
    """every pulse of servo pin RB<bit> in [t0, t1) is want_us wide (0.2 us
    resolution, +/- 1 cycle of interrupt latency jitter), 20 ms apart"""
    ps = [(r, f) for r, f in pin_pulses(writes, LATB, bit) if t0 <= r < t1]
    widths = sorted({f - r for r, f in ps})
    periods = sorted({b[0] - a[0] for a, b in zip(ps, ps[1:])})
    want = want_us * CYC_PER_US
    ok = len(ps) >= 2 and all(abs(w - want) <= 1 for w in widths) and \
        all(abs(p - 20 * CYC_PER_MS) <= 1 for p in periods)
    ck.check(ok, "%s pulse %.1f us every 20 ms in %d..%d ms (measured: %d pulses, widths %s us,"
             " periods %s ms)" % (name, want_us, t0 // CYC_PER_MS, t1 // CYC_PER_MS, len(ps),
                                  [w / CYC_PER_US for w in widths],
                                  [p / CYC_PER_MS for p in periods]))


# ---- scenarios ----------------------------------------------------------------------

def rotation_script(log, t):
    """The rotation scenario's command file; t: the times (cycles) of its steps."""
    s = Script()
    # Sin high (the baton is ours); the central control as i2c2par at 0x10, its
    # 8-bit port (the last data byte it received) on nodes cp0..cp7
    head = ["module load i2c2par central",
            "central.Slave_Address = %d" % CC["CHAIN_CENTRAL_ADDR"],
            "attach sda central.SDA",
            "attach scl central.SCL"]
    for k in range(8):
        head += ["node cp%d" % k, "attach cp%d central.p%d" % (k, k)]
    s.head = common_head(log, head)
    bus = Bus(s)
    addr = t["addr"]
    bus.frame(t["offer"], 0, [CC["CC_ENUM_OFFER"], addr])
    # pitch = 4500 sin(0 * t + 1 * 1571 mrad) = 4500 cdeg -> 1.75 ms
    bus.frame(t["gait"], addr, set_gait(CC["GAIT_FORWARD"], 4500, 0, 1571, CC["CC_AXIS_PITCH"]))
    bus.frame(t["start"], 0, [CC["CC_START"]])
    bus.frame(t["status"], addr, [CC["CC_STATUS"]])
    # yaw = 12000 sin(-1571 mrad) = -12000 cdeg: beyond the servo, clamped to 1.0 ms
    bus.frame(t["gait2"], addr, set_gait(CC["GAIT_FORWARD"], 12000, 0, -1571, CC["CC_AXIS_YAW"]))
    return s


SAMPLE_PORT = ["central.p%d" % k for k in range(8)]  # ('node' crashes gpsim 0.31)


def received_by_central(out):
    """the i2c2par port values printed by SAMPLE_PORT, in order"""
    vals, cur = [], {}
    for m in re.finditer(r"attached to cp([0-7])\s.*?bitState=([01])", out, re.S):
        cur[int(m.group(1))] = m.group(2) == "1"
        if len(cur) == 8:
            vals.append(sum(1 << k for k, hi in cur.items() if hi))
            cur = {}
    return vals


def scenario_rotation(build_dir, workdir):
    """Two runs of the same (deterministic) simulation: the first finds when
    the firmware writes its reply bytes to SSPBUF, the second samples what the
    central control (i2c2par, slave 0x10) received from the bus at those
    times. gpsim 0.31's MSSP master keeps SDA driven through the ACK clock
    after a 0 bit, so the firmware's view of the ACKs proves little there;
    the slave's view does."""
    cod = os.path.join(build_dir, "fw-rotation.cod")
    log = os.path.join(workdir, "writes.log")
    ms = CYC_PER_MS
    t = {"addr": 0x21,  # chain position k = 1
         "offer": 100 * ms, "gait": 120 * ms, "start": 130 * ms, "status": 220 * ms,
         "gait2": 240 * ms, "end": 330 * ms}
    addr = t["addr"]

    run_gpsim(cod, rotation_script(log, t).text(t["end"]), workdir)
    w = parse_writes(log)
    ck = Checks()

    # 1. after reset: both servos held straight
    check_pulses(ck, w, "pitch (RB2)", 2, 20 * ms, t["offer"], 1500)
    check_pulses(ck, w, "yaw (RB3)", 3, 20 * ms, t["offer"], 1500)
    # 2. discovery: Sout and the reply
    sout = first_rise(w, LATC, 1)
    ck.check(sout is not None and t["offer"] < sout < t["offer"] + 10 * ms,
             "Sout (RC1) rises after ENUM_OFFER (at %s ms)" % (sout and sout / ms))
    central = CC["CHAIN_CENTRAL_ADDR"]
    enum_want = [central << 1, CC["CC_ENUM_REPLY"], addr, CC["MT_ROTATION"]]
    enum_w = [(c, v) for c, a, v in w if a == SSPBUF and t["offer"] <= c < t["gait"]]
    ck.check([v for c, v in enum_w] == enum_want,
             "ENUM_REPLY to 0x10 written to the MSSP: %s, want %s"
             % ([hex(v) for c, v in enum_w], [hex(b) for b in enum_want]))
    # 3. the gait's set-point on the pitch servo, yaw still straight
    check_pulses(ck, w, "pitch (RB2)", 2, t["start"] + 20 * ms, t["status"], 1750)
    check_pulses(ck, w, "yaw (RB3)", 3, t["start"] + 20 * ms, t["status"], 1500)
    # 4. STATUS is answered: rotation module, running, gait 1, no flags
    status_want = [central << 1, CC["CC_STATUS_REPLY"], addr, CC["MT_ROTATION"],
                   CC["CC_STATE_RUNNING"], CC["GAIT_FORWARD"], 0]
    status_w = [(c, v) for c, a, v in w if a == SSPBUF and t["status"] <= c < t["gait2"]]
    ck.check([v for c, v in status_w] == status_want,
             "STATUS_REPLY to 0x10 written to the MSSP: %s, want %s"
             % ([hex(v) for c, v in status_w], [hex(b) for b in status_want]))
    # 5. a set-point beyond the servo's range clamps; pitch back to straight
    check_pulses(ck, w, "yaw (RB3), -12000 cdeg clamped", 3, t["gait2"] + 20 * ms, t["end"], 1000)
    check_pulses(ck, w, "pitch (RB2)", 2, t["gait2"] + 20 * ms, t["end"], 1500)

    # 6. second run: what the central control received. Data byte j is on
    # its port once the next byte is written (or after the stop)
    if len(enum_w) == len(enum_want) and len(status_w) == len(status_want):
        s = rotation_script(log + "2", t)
        samples = []
        for frame in (enum_w, status_w):
            cycles = [c for c, v in frame]
            for c in cycles[2:] + [cycles[-1] + 2 * ms]:
                s.at(c - 1, *SAMPLE_PORT)
                samples.append(c)
        out = run_gpsim(cod, s.text(t["end"]), workdir)
        got = received_by_central(out)
        want = enum_want[1:] + status_want[1:]
        ck.check(got == want, "the central control (slave 0x10) received ENUM_REPLY and "
                 "STATUS_REPLY from the bus: %s, want %s"
                 % ([hex(b) for b in got], [hex(b) for b in want]))
    return ck


def scenario_central(build_dir, workdir):
    cod = os.path.join(build_dir, "fw-central.cod")
    log = os.path.join(workdir, "writes.log")
    s = Script()
    # Sin low: no module closes the ring
    s.head = common_head(log, ["pu_sin.voltage = 0.0"])
    ms = CYC_PER_MS
    t_end = 400 * ms
    run_gpsim(cod, s.text(t_end), workdir)
    w = parse_writes(log)
    ck = Checks()
    sout = first_rise(w, LATC, 1)
    ck.check(sout is not None and sout < 5 * ms,
             "Sout (RC1) raised at start-up (at %s ms)" % (sout and sout / ms))
    got = sspbuf_bytes(w, 0, t_end)
    ck.check(got[:1] == [0x00], "ENUM_OFFER started as a general call: SSPBUF writes %s"
             % [hex(b) for b in got[:4]])
    uart = "".join(chr(v) for c, a, v in w if a == TXREG)
    for text in ("discovery: no reply at position 0 (address 0x20) within 200 ms; "
                 "continuing with 0 modules\r\n", "chain: (0 modules)\r\n"):
        ck.check(text in uart, "UART (TXREG) log line %r" % text)
    return ck


def size_table(build_dir, progs):
    """hal-pic/README.md's memory table, from the build's .size files, largest
    program first"""
    size_re = re.compile(r"flash (\d+) / (\d+) bytes \(([\d.]+)%\), RAM (\d+) / (\d+) bytes \(([\d.]+)%")
    rows = []
    for prog in progs:
        with open(os.path.join(build_dir, "fw-" + prog + ".size")) as f:
            m = size_re.search(f.read())
        flash, _, fpct, ram, _, rpct = m.groups()
        rows.append((int(flash), "| %s | %s B (%s %%) | %s B (%s %%) |" % (prog, flash, fpct, ram, rpct)))
    return [r for _, r in sorted(rows, key=lambda r: (-r[0], r[1]))]


def check_size_table(repo, build_dir, progs):
    """the README's table must be what this build measured"""
    readme = os.path.join(repo, "hal-pic", "README.md")
    want = size_table(build_dir, progs)
    with open(readme) as f:
        have = [l.rstrip() for l in f if re.match(r"^\| [a-z]+ \| \d+ B ", l)]
    if have != want:
        print("FAIL: hal-pic/README.md's memory table is not what the build measured; put these rows in it:")
        print("\n".join(want))
        return 1
    print("build: hal-pic/README.md's memory table matches the build")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario", choices=["build", "rotation", "central"])
    ap.add_argument("--repo", required=True)
    ap.add_argument("--build-dir", required=True)
    ap.add_argument("--keep", action="store_true", help="keep the gpsim work directory")
    a = ap.parse_args()

    load_commands(os.path.abspath(a.repo))
    build(os.path.abspath(a.repo), os.path.abspath(a.build_dir))
    if a.scenario == "build":
        progs = sorted(os.path.basename(os.path.dirname(m)) for m in
                       glob.glob(os.path.join(a.repo, "firmware", "*", "main.c")))
        if not progs:
            print("FAIL: no firmware/*/main.c")
            return 1
        for prog in progs:
            if not os.path.isfile(os.path.join(a.build_dir, "fw-" + prog + ".hex")):
                print("FAIL: no fw-%s.hex" % prog)
                return 1
        print("build: all programs built and fit the part")
        return check_size_table(a.repo, a.build_dir, progs)
    if shutil.which("gpsim") is None:
        skip("gpsim is not installed (tools/pic-toolchain.sh installs it)")
    workdir = tempfile.mkdtemp(prefix="gpsim-%s-" % a.scenario)
    try:
        fn = scenario_rotation if a.scenario == "rotation" else scenario_central
        ck = fn(os.path.abspath(a.build_dir), workdir)
    except subprocess.TimeoutExpired:
        print("FAIL: gpsim timed out (files in %s)" % workdir)
        return 1
    if ck.failed or a.keep:
        print("gpsim files kept in %s" % workdir)
    else:
        shutil.rmtree(workdir, ignore_errors=True)
    print("%s: %d check(s) failed" % (a.scenario, ck.failed) if ck.failed else
          "%s: all checks passed" % a.scenario)
    return 1 if ck.failed else 0


if __name__ == "__main__":
    sys.exit(main())
