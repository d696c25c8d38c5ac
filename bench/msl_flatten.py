#!/usr/bin/env python3
"""Flattening time of Modelica Standard Library models whose devices are
large inlined functions (Spice3's semiconductors) or many instances.

For each model, `mocompile --emit flat -q` with
MODELICAPATH=<shared>/third_party/msl-3.2.2, best of --runs runs: prints the
model, the flat model's equation count (lines between `equation` and `end`),
the wall time in seconds and the peak resident memory (ru_maxrss of the child).
Usage:
  bench/msl_flatten.py [--build DIR] [--shared DIR] [--runs N] [MODEL ...]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

DEFAULT_MODELS = [
    "Modelica.Electrical.Spice3.Examples.Inverter",
    "Modelica.Electrical.Spice3.Examples.Nand",
    "Modelica.Electrical.Spice3.Examples.FourInverters",
    "Modelica.Electrical.Spice3.Examples.Spice3BenchmarkDifferentialPair",
    "Modelica.Electrical.Spice3.Examples.Spice3BenchmarkFourBitBinaryAdder",
    "Modelica.Electrical.Analog.Examples.CauerLowPassSC",
]


def shared_dir(arg):
    for d in (arg, os.path.join(ROOT, "..", "shared"), os.environ.get("MO_SHARED_DIR")):
        if d and os.path.isdir(os.path.join(d, "third_party", "msl-3.2.2")):
            return d
    print("SKIPPED: no shared folder with third_party/msl-3.2.2 (pass --shared or set MO_SHARED_DIR)")
    sys.exit(0)


def flatten_once(mocompile, msl, model, work):
    src = os.path.join(work, "Bench.mo")
    with open(src, "w") as f:
        f.write("model Bench\n  extends %s;\nend Bench;\n" % model)
    out = os.path.join(work, "flat.mo")
    env = dict(os.environ, MODELICAPATH=msl)
    err = os.path.join(work, "stderr.txt")
    began = time.monotonic()
    with open(err, "w") as e:
        p = subprocess.Popen([mocompile, src, "--emit", "flat", "-q", "-o", out], env=env,
                             stdout=subprocess.DEVNULL, stderr=e)
        _, status, usage = os.wait4(p.pid, 0)  # this child's own peak memory
    seconds = time.monotonic() - began
    rss_mb = usage.ru_maxrss / 1024.0
    if os.waitstatus_to_exitcode(status) != 0:
        with open(err) as e:
            first = (e.read().strip().splitlines() or ["exit status %d" % status])[0]
        return None, seconds, rss_mb, first
    equations, inside = 0, False
    with open(out) as f:
        for line in f:
            if line.startswith("equation"):
                inside = True
            elif line.startswith("end "):
                inside = False
            elif inside and line.strip():
                equations += 1
    return equations, seconds, rss_mb, ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--shared")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("models", nargs="*", default=DEFAULT_MODELS)
    a = ap.parse_args()
    msl = os.path.join(shared_dir(a.shared), "third_party", "msl-3.2.2")
    mocompile = os.path.join(a.build, "tools", "mocompile")
    print("| model | flat equations | flatten s | peak RSS MB |")
    print("|---|---:|---:|---:|")
    for model in a.models:
        best, equations, error, rss = None, None, "", 0.0
        for _ in range(max(1, a.runs)):
            with tempfile.TemporaryDirectory() as work:
                equations, seconds, rss_mb, error = flatten_once(mocompile, msl, model, work)
            if error:
                break
            best = seconds if best is None else min(best, seconds)
            rss = max(rss, rss_mb)
        name = model.replace("Modelica.Electrical.", "")
        if error:
            print("| %s | - | - | - | %s" % (name, error[:120]))
        else:
            print("| %s | %d | %.2f | %.0f |" % (name, equations, best, rss), flush=True)


if __name__ == "__main__":
    main()
