#!/usr/bin/env python3
"""Robot-level hidden effects study (issue 40, requirement 3).

`chainsim calibrate --robot` on speed tables made by the simulator itself on a
robot with one hidden change: a knob of the catalogue (drive stall torque or
free speed, wheel friction, pad friction, arm servo torque, extension force,
wall friction) or a change outside it (a mass, a slope offset, a pipe
diameter), and two nulls (the shipped robots unchanged).

Each case, as robot_calibration_pairs_test.cpp does it, writes the changed
module as its own module file (the shipped file with its numbers scaled in the
text, not through the calibration's knob code) and/or the changed scene, runs
the hidden robot on every row's scene with `chainsim run` (the same runs as a
calibration's: --duration, speed of the head's first body along the pipe's
first segment from --window-start) to make the "measured" table (rounded to
0.01 cm/s), then calibrates the shipped scenes against it and reads
report.json.

A case is met when:
  * knob change: the changed knob is named with its factor within 10 % of the
    hidden one, nothing else is named, and the gap shrinks (after < before);
  * change outside the knobs: the verdict is `unexplained` (whatever effect it
    accepted on the way) and the gap does not grow; naming a knob that mimics
    the change with verdict `explained` is a miss;
  * null: nothing is named (`no_missing_effect`).

Run from the source tree (the scenes are read from it; chainsim finds its
fw-* programs beside its executable):

  nice -n 10 python3 tests/physics-server/analysis/robot_calibration/robot_hidden_study.py \
      --chainsim build/bin/chainsim [--jobs 2] [--cases h-stall-0.8,null-heli] \
      [--work /tmp/robot-hidden-study] [--list]

It prints one line per case as it ends and a Markdown table at the end, and
writes WORK/results.json and WORK/results.md. Cases and seeds are fixed here
(the scenes' seed 1); results are deterministic for a given build.
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "..", ".."))
DURATION = 2.5
WINDOW = 1.0
HELI_SLOPES = ["0", "30", "45", "60", "90"]
INCH_SLOPES = ["0", "15", "30", "45", "60"]

# Each case: name, robot scene (at 30 degrees), rows, module changes [(type, key, factor)],
# scene changes {"slope_offset_deg": d, "diameter_m": x, "wall_mu_factor": f} (the hidden
# scenes only), expected:
#   {"knob": name, "factor": f} | {"outside": description} | {"null": True}
#   | {"unobservable": True} (a change the table does not show: nothing should be named)


def heli(name, hidden, expect, modules=(), **scene_changes):
    """a case on the helicoidal module's table"""
    return dict(name=name, scene="helicoidal-30.yaml", slopes=HELI_SLOPES, modules=list(modules),
                scene_changes=scene_changes, expect=expect, hidden=hidden)


def inch(name, hidden, expect, modules=(), **scene_changes):
    """a case on the inchworm's table"""
    return dict(name=name, scene="inchworm-30.yaml", slopes=INCH_SLOPES, modules=list(modules),
                scene_changes=scene_changes, expect=expect, hidden=hidden)


def knob(name, factor):
    return {"knob": name, "factor": factor}


CASES = [
    # nulls: the shipped robots, unchanged
    heli("null-heli", "none (shipped helicoidal)", {"null": True}),
    inch("null-inch", "none (shipped inchworm)", {"null": True}),
    # helicoidal: servo (drive motor) parameters
    heli("h-stall-0.8", "drive stall torque x0.8", knob("drive_stall", 0.8),
         [("helicoidal", "stall_torque_nm", 0.8)]),
    heli("h-stall-1.25", "drive stall torque x1.25", knob("drive_stall", 1.25),
         [("helicoidal", "stall_torque_nm", 1.25)]),
    heli("h-free-1.15", "drive free speed x1.15", knob("drive_free_speed", 1.15),
         [("helicoidal", "free_speed_rad_s", 1.15)]),
    heli("h-free-0.85", "drive free speed x0.85", knob("drive_free_speed", 0.85),
         [("helicoidal", "free_speed_rad_s", 0.85)]),
    # helicoidal: wheel friction (both wheel sets). The wheels grip about six times what the stall
    # thrust needs: from x1 down to x0.1 the table moves 0.03 cm/s at most, at x0.08 the
    # module slides down the 60 and 90 degree pipes; the knob's range is 0.3..2. A change the table
    # cannot show: the right answer is nothing named (counted apart from the cases and the nulls).
    heli("h-wheelmu-0.5", "wheel friction x0.5 (mu 0.3; the table does not move)", {"unobservable": True},
         [("helicoidal", "mu", 0.5)]),
    # helicoidal: outside the knobs (no mass, slope or bore knob)
    heli("h-mass-1.3", "module mass x1.3 (pig and head)", {"outside": "mass"},
         [("helicoidal", "mass_kg", 1.3)]),
    heli("h-slope+3", "pipe at slope + 3 deg in every row", {"outside": "slope offset"},
         slope_offset_deg=3),
    heli("h-pipe-42", "pipe bore 42 mm instead of 40", {"outside": "pipe diameter"}, diameter_m=0.042),
    # inchworm: the extension, the pads, the arm servos, the wall
    inch("i-ext-0.7", "extension force x0.7", knob("extension_force", 0.7), [("extension", "fmax_n", 0.7)]),
    inch("i-ext-1.3", "extension force x1.3", knob("extension_force", 1.3), [("extension", "fmax_n", 1.3)]),
    inch("i-pad-0.8", "pad friction x0.8", knob("pad_friction", 0.8), [("support", "mu", 0.8)]),
    inch("i-grip-0.6", "support arm servos' kt x0.6 (all three)", knob("arm_grip_torque", 0.6),
         [("support", "kt", 0.6)]),
    inch("i-wall-0.7", "wall friction x0.7 (mu 0.42)", knob("wall_friction", 0.7), wall_mu_factor=0.7),
    inch("i-pad-1.3", "pad friction x1.3", knob("pad_friction", 1.3), [("support", "mu", 1.3)]),
    inch("i-slope+3", "pipe at slope + 3 deg in every row", {"outside": "slope offset"}, slope_offset_deg=3),
    inch("i-mass-1.3", "every body's mass x1.3 (supports and extension)", {"outside": "mass"},
         [("support", "mass_kg", 1.3), ("extension", "mass_kg", 1.3)]),
]

ARM_SERVO = "{name: arm_servo, type: servo, joint: arm_top}"
ARM_SERVO_KT = 0.14   # the World's servo model (servo_model.h), used by the driven arm servo


def read(path):
    with open(path) as f:
        return f.read()


def scale_numbers(text, key, factor):
    """every number after `key: ` in text times factor (as the pairs test)"""
    count = [0]

    def sub(m):
        count[0] += 1
        return m.group(1) + "%.6g" % (float(m.group(2)) * factor)

    out = re.sub(r"(\b" + re.escape(key) + r": )([-0-9.eE+]+)", sub, text)
    if count[0] == 0:
        raise SystemExit("no '%s:' to scale" % key)
    return out


def hidden_module(mtype, text, key, factor):
    text = scale_numbers(text, key, factor)
    if mtype == "support" and key == "kt":   # the driven arm servo uses the World's kt: give it its own
        if ARM_SERVO not in text:
            raise SystemExit("support.yaml: the arm servo line changed")
        text = text.replace(ARM_SERVO, "{name: arm_servo, type: servo, joint: arm_top, servo: {kt: %.6g}}"
                            % (ARM_SERVO_KT * factor))
    return text


def pipe_axis(slope_deg):
    s = math.radians(slope_deg)
    return (math.cos(s), 0.0, math.sin(s))


def head_speed(trace, t0, axis):
    """head_speed.cpp: the head's first body along axis from t0 to the end, cm/s"""
    with open(trace) as f:
        rows = csv.reader(f)
        names = next(rows)
        body = names[1][:-1]
        cx, cy, cz = names.index(body + "x"), names.index(body + "y"), names.index(body + "z")
        a = b = None
        for r in rows:
            t = float(r[0])
            if t + 1e-9 < t0:
                continue
            p = (t, float(r[cx]), float(r[cy]), float(r[cz]))
            if a is None:
                a = p
            b = p
    d = [b[i] - a[i] for i in (1, 2, 3)]
    return 100 * sum(d[i] * axis[i] for i in range(3)) / (b[0] - a[0])


def make_case(c, d, chainsim, jobs):
    """nominal-<slope>.yaml, hidden-<slope>.yaml and table.csv in d"""
    os.makedirs(d, exist_ok=True)
    types = {}
    for mtype, key, f in c["modules"]:
        text = types.get(mtype) or read(os.path.join(SRC, "scenes", "modules", mtype + ".yaml"))
        types[mtype] = hidden_module(mtype, text, key, f)
    module_types = ""
    if types:
        module_types = "module_types:\n"
        for mtype, text in sorted(types.items()):
            with open(os.path.join(d, "hidden-%s.yaml" % mtype), "w") as f:
                f.write(text)
            module_types += "  %s: hidden-%s.yaml\n" % (mtype, mtype)
    base = read(os.path.join(SRC, "scenes", c["scene"]))
    sc = c["scene_changes"]
    jobs_list = []
    for slope in c["slopes"]:
        s = re.sub(r"slope_deg: 30\b", "slope_deg: " + slope, base)
        with open(os.path.join(d, "nominal-%s.yaml" % slope), "w") as f:
            f.write(s)
        hidden_slope = float(slope) + sc.get("slope_offset_deg", 0)
        if hidden_slope <= 90:
            h = re.sub(r"slope_deg: 30\b", "slope_deg: %g" % hidden_slope, base)
        else:   # past vertical: the pipe rises at 180 - slope the other way (heading 180), the same axis
            h = re.sub(r"slope_deg: 30\b", "slope_deg: %g" % (180 - hidden_slope), base)
            h, n = re.subn(r"\n(\s+)inner_diameter_m:", r"\n\1heading_deg: 180\n\1inner_diameter_m:", h)
            assert n == 1
        if "diameter_m" in sc:
            h, n = re.subn(r"inner_diameter_m: [0-9.]+", "inner_diameter_m: %g" % sc["diameter_m"], h)
            assert n == 1
        if "wall_mu_factor" in sc:
            def mu(m):
                return m.group(1) + "%.6g" % (float(m.group(2)) * sc["wall_mu_factor"])
            h, n = re.subn(r"(material: \{mu: )([0-9.]+)", mu, h)
            assert n == 1
        at = h.find("\nchain: ")
        assert at >= 0
        h = h[:at + 1] + module_types + h[at + 1:]
        path = os.path.join(d, "hidden-%s.yaml" % slope)
        with open(path, "w") as f:
            f.write(h)
        jobs_list.append((slope, path, hidden_slope))

    def run(job):
        slope, path, hidden_slope = job
        out = os.path.join(d, "hidden-runs", slope)
        shutil.rmtree(out, ignore_errors=True)
        subprocess.run([chainsim, "run", path, "--out", out, "--duration", str(DURATION), "--quiet",
                        "--on-divergence", "warn"], check=True, stdout=subprocess.DEVNULL)
        return head_speed(os.path.join(out, "trace.csv"), WINDOW, pipe_axis(hidden_slope))

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        speeds = list(ex.map(run, jobs_list))
    with open(os.path.join(d, "table.csv"), "w") as f:
        f.write("# hidden: %s\nslope_deg,real_speed_cm_s\n" % c["hidden"])
        for slope, v in zip(c["slopes"], speeds):
            f.write("%s,%.2f\n" % (slope, v))
    return speeds


def judge(c, j):
    effects = [(e["name"], e["factor"]) for e in j["effects"]]
    before, after = j["gap_before"], j["gap_after"]
    ex = c["expect"]
    if "null" in ex or "unobservable" in ex:
        return not effects, "nothing named" if not effects else "named " + ", ".join(n for n, _ in effects)
    if "outside" in ex:
        ok = j["verdict"] == "unexplained" and after <= before + 1e-9
        return ok, "verdict %s" % j["verdict"]
    named = dict(effects)
    if ex["knob"] not in named:
        return False, "%s not named" % ex["knob"]
    ratio = named[ex["knob"]] / ex["factor"]
    others = [n for n in named if n != ex["knob"]]
    ok = abs(ratio - 1) <= 0.10 and not others and after < before
    why = "factor %.3f (x%.3f of hidden)" % (named[ex["knob"]], ratio)
    if others:
        why += "; also named " + ", ".join(others)
    return ok, why


def run_case(c, work, chainsim, jobs):
    d = os.path.join(work, c["name"])
    shutil.rmtree(d, ignore_errors=True)
    t0 = time.time()
    speeds = make_case(c, d, chainsim, jobs)
    t1 = time.time()
    out = os.path.join(d, "out")
    cmd = [chainsim, "calibrate", "--robot", os.path.join(d, "table.csv"), "--scene-template",
           os.path.join(d, "nominal-{slope}.yaml"), "--duration", str(DURATION), "--window-start", str(WINDOW),
           "--jobs", str(jobs), "--out", out, "--quiet"]
    rc = subprocess.run(cmd).returncode
    t2 = time.time()
    with open(os.path.join(out, "report.json")) as f:
        j = json.load(f)
    ok, why = judge(c, j)
    effects = ["%s x%.3f" % (e["name"], e["factor"]) for e in j["effects"]]
    best = sorted((cand for cand in j["candidates"] if cand["round"] == 1), key=lambda x: x["gap"])
    return dict(name=c["name"], hidden=c["hidden"], expect=c["expect"], exit_code=rc, verdict=j["verdict"],
                named=effects, gap_before=j["gap_before"], gap_after=j["gap_after"],
                gap_leave_one_out=j.get("gap_leave_one_out"), settings=j["evaluations"], runs=j["runs"],
                table=[round(v, 2) for v in speeds], rows=j["rows"], missed=j["missed"],
                round1=[(x["name"], round(x["gap"], 3),
                         round(list(x["settings"].values())[-1]["factor"], 3) if x["settings"] else None)
                        for x in best],
                pairs=[(p["names"], round(p["gap"], 3), p["accepted"], p["why"]) for p in j["pairs"]],
                aliases=[(a["names"], a["factors"]) for a in j["aliases"]],
                met=ok, why=why, wall_table_s=round(t1 - t0, 1), wall_calibrate_s=round(t2 - t1, 1),
                report_wall_s=j["wall_s"])


def markdown(results):
    lines = ["| case | hidden | named (verdict) | gap before -> after (cm/s) | settings | wall | met? |",
             "|---|---|---|---|---|---|---|"]
    for r in results:
        named = ", ".join(r["named"]) or "nothing"
        lines.append("| %s | %s | %s (%s) | %.3f -> %.3f | %d | %.0f s | %s: %s |" % (
            r["name"], r["hidden"], named, r["verdict"], r["gap_before"], r["gap_after"], r["settings"],
            r["wall_table_s"] + r["wall_calibrate_s"], "yes" if r["met"] else "**no**", r["why"]))
    nulls = [r for r in results if "null" in r["expect"]]
    unobs = [r for r in results if "unobservable" in r["expect"]]
    others = [r for r in results if "null" not in r["expect"] and "unobservable" not in r["expect"]]
    knob = [r for r in others if "knob" in r["expect"]]
    lines.append("")
    lines.append("Cases met: %d / %d (knob changes %d / %d, changes outside the knobs %d / %d); "
                 "nulls clean: %d / %d; unobservable changes with nothing named: %d / %d." % (
                     sum(r["met"] for r in others), len(others), sum(r["met"] for r in knob), len(knob),
                     sum(r["met"] for r in others if r not in knob), len(others) - len(knob),
                     sum(r["met"] for r in nulls), len(nulls), sum(r["met"] for r in unobs), len(unobs)))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--chainsim", default=os.path.join(SRC, "build", "bin", "chainsim"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    ap.add_argument("--work", default="/tmp/robot-hidden-study")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    if a.list:
        for c in CASES:
            print("%-16s %s" % (c["name"], c["hidden"]))
        return 0
    want = [s for s in a.cases.split(",") if s]
    unknown = set(want) - {c["name"] for c in CASES}
    if unknown:
        raise SystemExit("unknown cases: " + ", ".join(sorted(unknown)))
    cases = [c for c in CASES if not want or c["name"] in want]
    os.makedirs(a.work, exist_ok=True)
    results = []
    for c in cases:
        r = run_case(c, a.work, os.path.abspath(a.chainsim), a.jobs)
        results.append(r)
        print("%-16s %-4s %-18s %.3f -> %.3f  %s  (%d settings, %.0f s)" % (
            r["name"], "met" if r["met"] else "MISS", r["verdict"], r["gap_before"], r["gap_after"],
            ", ".join(r["named"]) or "nothing", r["settings"], r["wall_table_s"] + r["wall_calibrate_s"]),
            flush=True)
        with open(os.path.join(a.work, "results.json"), "w") as f:
            json.dump(results, f, indent=1)
    md = markdown(results)
    with open(os.path.join(a.work, "results.md"), "w") as f:
        f.write(md + "\n")
    print()
    print(md)
    return 0 if all(r["met"] for r in results) else 2


if __name__ == "__main__":
    sys.exit(main())
