#!/usr/bin/env python3
"""How many example models of the Modelica Standard Library mocompile runs.

For each example that has a reference result in
<shared>/third_party/msl-reference-results-3.2.3 (Blocks, Electrical.Analog,
Mechanics.Translational, Mechanics.Rotational, Thermal.HeatTransfer), with
MODELICAPATH=<shared>/third_party/msl-3.2.2:
  flatten   mocompile --emit flat exits 0
  lower     mocompile --emit ode exits 0
  simulate  morun exits 0, run to the example's experiment annotation
            (StopTime, Tolerance, Interval; to the last reference time where
            that is later or StopTime is absent)
  matches   every compared signal of the reference that our result has is
            within 1e-3 of its range (plus 1e-6) of the reference at the
            reference rows away from events, and at least one is compared
With --package P (e.g. Modelica.Media.Examples, which has no reference
results): every complete model of the MSL sources under package P instead
(not partial, not a short definition), the same steps but `matches`.
Prints one row per example (with the first line of the error when a step
fails, or the timeout), the totals and the reasons of failure by count.
Usage:
  bench/msl_examples.py [--build DIR] [--shared DIR] [--only SUBSTRING] [--jobs N]
                        [--timeout SECONDS] [--list-matching] [--package P]
"""
import argparse
import bisect
import collections
import csv
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def shared_dir(arg, skip_code=None):
    for d in (arg, os.path.join(ROOT, "..", "shared"), os.environ.get("MO_SHARED_DIR")):
        if d and os.path.isdir(os.path.join(d, "third_party")):
            return d
    if skip_code is not None:
        print("SKIPPED: no shared folder beside the checkout (set MO_SHARED_DIR)")
        sys.exit(skip_code)
    sys.exit("no shared folder: pass --shared or set MO_SHARED_DIR")


def examples(ref_root):
    out = []
    for dirpath, _, files in os.walk(ref_root):
        if "comparisonSignals.txt" in files:
            rel = os.path.relpath(dirpath, os.path.dirname(ref_root))
            out.append((rel.replace(os.sep, "."), dirpath))
    return sorted(out)


def models_in(msl, package):
    """The complete models (`model`, not partial, not `model A = B`) nested
    in package `package` of the MSL sources, by their full names."""
    parts = package.split(".")
    d = msl
    for part in parts:
        if os.path.isdir(os.path.join(d, part)):
            d = os.path.join(d, part)
            continue
        one = os.path.join(d, part + ".mo")
        files = [one] if os.path.isfile(one) else [os.path.join(d, "package.mo")]
        break
    else:
        files = [os.path.join(dp, f) for dp, _, fs in os.walk(d) for f in fs if f.endswith(".mo")]
    out = []
    for f in sorted(files):
        with open(f, encoding="utf-8", errors="replace") as fh:
            text = fh.read()
        # Strings and comments hold words like `model` and `end`: blank them out.
        text = re.sub(r'"(\\.|[^"\\])*"|//[^\n]*|/\*.*?\*/', lambda m: re.sub(r"[^\n]", " ", m.group(0)),
                      text, flags=re.S)
        within = re.search(r"^\s*within\s+([\w.]*)\s*;", text, re.M)
        stack = within.group(1).split(".") if within and within.group(1) else []
        token = r"\b(?:(partial|encapsulated|replaceable|redeclare|final)\s+)*(model|block|class|package|record|" \
                r"function|connector|type|operator\s+record)\s+(?:extends\s+)?(\w+)\s*(=)?|\bend\s+(\w+)\s*;"
        for m in re.finditer(token, text):
            if m.group(5):
                if stack and stack[-1] == m.group(5):
                    stack.pop()
                continue
            if m.group(4):  # a short definition has no end
                continue
            stack.append(m.group(3))
            name = ".".join(stack)
            if m.group(2) == "model" and not m.group(1) and name.startswith(package + "."):
                out.append(name)
    return sorted(set(out))


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
    compared = 0
    for s in signals:
        if s not in ref or s not in ours:
            continue
        compared += 1
        y_ref, y = ref[s], ours[s]
        scale = (max(y_ref) - min(y_ref)) if y_ref else 0.0
        tol = 1e-3 * scale + 1e-6 + 1e-6 * max(abs(v) for v in y_ref)
        for t, v in zip(t_ref, y_ref):
            if any(abs(t - e) < 1e-3 * span for e in events):
                continue
            got = interpolate(t_ours, y, t)
            if not abs(got - v) <= tol:
                return "%s at t=%g: %g, reference %g" % (s, t, got, v)
    return "" if compared else "none of the compared signals is in result.csv"


def class_text(msl, cls):
    """The text of class `cls` in the MSL sources, or ''."""
    parts = cls.split(".")
    d, i = msl, 0
    while i < len(parts) - 1 and os.path.isdir(os.path.join(d, parts[i])):
        d = os.path.join(d, parts[i])
        i += 1
    f = os.path.join(d, parts[i] + ".mo")
    if not os.path.isfile(f):
        f = os.path.join(d, "package.mo")
    if not os.path.isfile(f):
        return ""
    with open(f, encoding="utf-8", errors="replace") as fh:
        text = fh.read()
    name = re.escape(parts[-1])
    m = re.search(r"\b(model|block|class)\s+%s\b" % name, text)
    if not m:
        return ""
    end = re.search(r"\bend\s+%s\s*;" % name, text[m.start():])
    return text[m.start():m.start() + end.end()] if end else text[m.start():]


def experiment(msl, cls):
    """StopTime, Tolerance and Interval of the class's experiment annotation (None when absent)."""
    m = re.search(r"experiment\s*\(([^)]*)\)", class_text(msl, cls))
    out = {}
    for key in ("StartTime", "StopTime", "Tolerance", "Interval"):
        v = re.search(r"\b%s\s*=\s*([-+0-9.eE]+)" % key, m.group(1)) if m else None
        out[key] = float(v.group(1)) if v else None
    return out


def first_error(text):
    for line in text.splitlines():
        if "error" in line:
            return line.strip()[:200]
    lines = [l for l in text.splitlines() if l.strip()]
    return (lines[-1] if lines else "no output")[:200]


def run(row, step, cmd, env, timeout):
    """The finished process, or None with row["why"] set."""
    try:
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        row["why"] = "%s: timeout after %g s" % (step, timeout)
        return None
    if p.returncode != 0:
        # Example.mo's temporary folder named: the same text on every run
        why = first_error(p.stderr).replace(os.path.dirname(cmd[1]) + os.sep, "")
        row["why"] = "%s: %s" % (step, why)
        return None
    return p


def reason(why):
    """A failure message without the example-specific parts (names, numbers, places)."""
    r = re.sub(r"\S+\.mo:\d+:\d+: ", "", why)
    r = re.sub(r"'[^']*'", "'…'", r)
    r = re.sub(r"\b[\w.\[\]]+ at t=.*", "signal off the reference", r)
    r = re.sub(r"\d+(\.\d+)?(e[-+]?\d+)?", "N", r)
    return r[:110]


def run_example(args, cls, ref_dir):
    env = dict(os.environ, MODELICAPATH=os.path.join(args.shared, "third_party", "msl-3.2.2"))
    with tempfile.TemporaryDirectory(prefix="mo_msl_") as tmp:
        main = os.path.join(tmp, "Example.mo")
        with open(main, "w") as f:
            f.write("model Example\n  extends %s;\nend Example;\n" % cls)
        row = {"class": cls, "flatten": False, "lower": False, "simulate": False, "matches": False, "why": ""}
        mocompile = os.path.join(args.build, "tools", "mocompile")
        for step, emit in (("flatten", "flat"), ("lower", "ode")):
            p = run(row, step, [mocompile, main, "--emit", emit], env, args.timeout)
            if p is None:
                return row
            row[step] = True
        ref_csv = os.path.join(ref_dir, cls.split(".")[-1] + ".csv")
        ref = read_csv(ref_csv) if os.path.isfile(ref_csv) else {}
        exp = experiment(os.path.join(args.shared, "third_party", "msl-3.2.2"), cls)
        stop = exp["StopTime"] or (ref["time"][-1] if ref.get("time") else 1.0)
        # The references were made with MSL 3.2.3, whose annotation may run
        # longer (ElastoGap: StopTime 5, 3.2.2 says 1): simulate as far as
        # the reference, or its later rows meet our last value.
        if ref.get("time") and ref["time"][-1] > stop:
            stop = ref["time"][-1]
        start = exp["StartTime"] or 0.0
        intervals = 2000
        if exp["Interval"]:
            intervals = max(1, min(20000, int(round((stop - start) / exp["Interval"]))))
        # At least as fine as the reference's own grid: the comparison
        # interpolates linearly between our rows, which on a coarser grid is
        # off by more than the tolerance where a signal bends (SimpleGearShift's
        # reference has rows every 0.005 s, its annotation says Interval=0.01).
        ts = ref.get("time", [])
        steps = sorted(b - a for a, b in zip(ts, ts[1:]) if b > a)
        if steps:  # the reference's usual spacing (its event rows aside)
            intervals = max(intervals, min(20000, int(round((stop - start) / steps[len(steps) // 2]))))
        out = os.path.join(tmp, "run")
        cmd = [os.path.join(args.build, "tools", "morun"), main, "--stop-time", repr(stop),
               "--intervals", str(intervals), "--aliases", "-o", out]
        if exp["Tolerance"]:
            cmd += ["--rtol", repr(min(exp["Tolerance"], 1e-6))]
        if run(row, "simulate", cmd, env, 3 * args.timeout) is None:
            return row
        row["simulate"] = True
        if not ref:
            row["why"] = "compare: the reference .csv is missing"
            return row
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
    ap.add_argument("--timeout", type=float, default=120.0,
                    help="seconds per mocompile step; simulation gets 3 times as long")
    ap.add_argument("--pinned", default=None,
                    help="file of classes (one a line, # comments) that must all match: exit 1 "
                         "when one does not, 77 when the shared folder is absent")
    ap.add_argument("--list-matching", action="store_true",
                    help="print only the classes that match their reference")
    ap.add_argument("--package", default=None,
                    help="every complete model under this package instead (no reference results)")
    args = ap.parse_args()
    args.shared = shared_dir(args.shared, 77 if args.pinned else None)
    ref_root = os.path.join(args.shared, "third_party", "msl-reference-results-3.2.3", "Modelica")
    if args.package:
        msl = os.path.join(args.shared, "third_party", "msl-3.2.2")
        todo = [(c, os.path.join(ref_root, "none")) for c in models_in(msl, args.package) if args.only in c]
    else:
        todo = [(c, d) for c, d in examples(ref_root) if args.only in c]
    pinned = None
    if args.pinned:
        with open(args.pinned) as f:
            pinned = [l.split("#")[0].strip() for l in f if l.split("#")[0].strip()]
        missing = set(pinned) - {c for c, _ in todo}
        if missing:
            sys.exit("pinned classes without a reference result: " + ", ".join(sorted(missing)))
        todo = [(c, d) for c, d in todo if c in pinned]
    def one(cd):
        try:
            row = run_example(args, *cd)
        except Exception as e:  # a bench bug must not lose the other rows
            row = {"class": cd[0], "flatten": False, "lower": False, "simulate": False,
                   "matches": False, "why": "bench: %s" % e}
        print("%s: %s" % (row["class"], row["why"] or "matches"), file=sys.stderr, flush=True)
        return row
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        rows = list(pool.map(one, todo))
    if args.list_matching:
        for r in rows:
            if r["matches"]:
                print(r["class"])
        return
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
    counts = collections.Counter(reason(r["why"]) for r in rows if r["why"])
    print("\nreasons of the first failure, by count:")
    for why, k in counts.most_common():
        print("%4d  %s" % (k, why))
    if pinned is not None and not all(r["matches"] for r in rows):
        sys.exit("a pinned example no longer matches its reference")


if __name__ == "__main__":
    main()
