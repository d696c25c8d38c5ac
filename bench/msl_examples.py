#!/usr/bin/env python3
"""How many example models of the Modelica Standard Library mocompile runs.

For each example that has a reference result in
<shared>/third_party/msl-reference-results-3.2.3 (Blocks, Electrical.Analog,
Mechanics.Translational, Mechanics.Rotational, Thermal.HeatTransfer), with
MODELICAPATH=<shared>/third_party/msl-3.2.2:
  flatten   mocompile --emit flat exits 0
  lower     mocompile --emit ode exits 0
  simulate  morun --stop-time <last reference time> exits 0
  matches   every compared signal is within 1e-3 of its range (plus 1e-6)
            of the reference at the reference rows away from events
Prints one row per example (with the first line of the error when a step
fails) and the totals. Usage:
  bench/msl_examples.py [--build DIR] [--shared DIR] [--only SUBSTRING] [--jobs N]
"""
import argparse
import bisect
import csv
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def shared_dir(arg):
    for d in (arg, os.path.join(ROOT, "..", "shared"), os.environ.get("MO_SHARED_DIR")):
        if d and os.path.isdir(os.path.join(d, "third_party")):
            return d
    sys.exit("no shared folder: pass --shared or set MO_SHARED_DIR")


def examples(ref_root):
    out = []
    for dirpath, _, files in os.walk(ref_root):
        if "comparisonSignals.txt" in files:
            rel = os.path.relpath(dirpath, os.path.dirname(ref_root))
            out.append((rel.replace(os.sep, "."), dirpath))
    return sorted(out)


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h: [] for h in header}
    for r in rows[1:]:
        if len(r) != len(header):
            continue
        for h, v in zip(header, r):
            try:
                cols[h].append(float(v))
            except ValueError:
                cols[h].append(float("nan"))
    return cols


def interpolate(ts, ys, t):
    i = bisect.bisect_left(ts, t)
    if i <= 0:
        return ys[0]
    if i >= len(ts):
        return ys[-1]
    t0, t1 = ts[i - 1], ts[i]
    if t1 == t0:
        return ys[i]
    w = (t - t0) / (t1 - t0)
    return ys[i - 1] * (1 - w) + ys[i] * w


def compare(ref_dir, name, result_csv):
    """'' when every compared signal matches, else the first mismatch."""
    ref = read_csv(os.path.join(ref_dir, name.split(".")[-1] + ".csv"))
    with open(os.path.join(ref_dir, "comparisonSignals.txt")) as f:
        signals = [s.strip() for s in f if s.strip() and s.strip() != "time"]
    ours = read_csv(result_csv)
    t_ref, t_ours = ref["time"], ours.get("time")
    if not t_ours:
        return "no time column in result.csv"
    events = {t for a, t in zip(t_ref, t_ref[1:]) if a == t}
    span = (t_ref[-1] - t_ref[0]) or 1.0
    for s in signals:
        if s not in ref:
            continue
        if s not in ours:
            return "signal %s not in result.csv" % s
        y_ref, y = ref[s], ours[s]
        scale = (max(y_ref) - min(y_ref)) if y_ref else 0.0
        tol = 1e-3 * scale + 1e-6 + 1e-6 * max(abs(v) for v in y_ref)
        for t, v in zip(t_ref, y_ref):
            if any(abs(t - e) < 1e-3 * span for e in events):
                continue
            got = interpolate(t_ours, y, t)
            if not abs(got - v) <= tol:
                return "%s at t=%g: %g, reference %g" % (s, t, got, v)
    return ""


def first_error(text):
    for line in text.splitlines():
        if "error" in line:
            return line.strip()[:200]
    lines = [l for l in text.splitlines() if l.strip()]
    return (lines[-1] if lines else "no output")[:200]


def run_example(args, cls, ref_dir):
    env = dict(os.environ, MODELICAPATH=os.path.join(args.shared, "third_party", "msl-3.2.2"))
    with tempfile.TemporaryDirectory(prefix="mo_msl_") as tmp:
        main = os.path.join(tmp, "Example.mo")
        with open(main, "w") as f:
            f.write("model Example\n  extends %s;\nend Example;\n" % cls)
        row = {"class": cls, "flatten": False, "lower": False, "simulate": False, "matches": False, "why": ""}
        mocompile = os.path.join(args.build, "tools", "mocompile")
        for step, emit in (("flatten", "flat"), ("lower", "ode")):
            p = subprocess.run([mocompile, main, "--emit", emit], env=env, capture_output=True,
                               text=True, timeout=600)
            if p.returncode != 0:
                row["why"] = "%s: %s" % (step, first_error(p.stderr))
                return row
            row[step] = True
        ref = read_csv(os.path.join(ref_dir, cls.split(".")[-1] + ".csv"))
        stop = ref["time"][-1] if ref.get("time") else 1.0
        out = os.path.join(tmp, "run")
        p = subprocess.run([os.path.join(args.build, "tools", "morun"), main, "--stop-time", repr(stop),
                            "--intervals", "2000", "--aliases", "-o", out],
                           env=env, capture_output=True, text=True, timeout=900)
        if p.returncode != 0:
            row["why"] = "simulate: " + first_error(p.stderr)
            return row
        row["simulate"] = True
        why = compare(ref_dir, cls, os.path.join(out, "result.csv"))
        row["matches"] = not why
        row["why"] = "compare: " + why if why else ""
        return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--shared", default=None)
    ap.add_argument("--only", default="")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args()
    args.shared = shared_dir(args.shared)
    ref_root = os.path.join(args.shared, "third_party", "msl-reference-results-3.2.3", "Modelica")
    todo = [(c, d) for c, d in examples(ref_root) if args.only in c]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        rows = list(pool.map(lambda cd: run_example(args, *cd), todo))
    print("| example | flatten | lower | simulate | matches | first failure |")
    print("|---|:-:|:-:|:-:|:-:|---|")
    mark = lambda b: "yes" if b else "-"
    for r in rows:
        print("| %s | %s | %s | %s | %s | %s |" % (r["class"], mark(r["flatten"]), mark(r["lower"]),
                                                 mark(r["simulate"]), mark(r["matches"]),
                                                 r["why"].replace("|", "\\|")))
    n = len(rows)
    print("\nof %d examples: %d flatten, %d lower, %d simulate, %d match the reference" % (
        n, sum(r["flatten"] for r in rows), sum(r["lower"] for r in rows),
        sum(r["simulate"] for r in rows), sum(r["matches"] for r in rows)))


if __name__ == "__main__":
    main()
