#!/usr/bin/env python3
"""How a study's cost grows with the sample ticks of a sampled-data model.

Each tick that changes the model is a phase of the multi-phase collocation
(docs/events.md, "Sampled-data models"). This runs the estimation of
tests/e2e/data/SampledEstimate.mop (a first-order plant under a sampled
proportional controller, 2 s, 20 samples) with the sample period T set so
that the horizon has N ticks, and prints per N the phases, morun's compile
and solve seconds (summary.json's timings) and Ipopt's iterations.

Usage: bench/sampled_phases.py [--morun build/tools/morun] [N ...]
(default N: 10 100 200 500 1000). Each N in a fresh cache directory, so the
compile time is a real compilation.
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "e2e" / "data"


def run(morun: str, ticks: int, work: pathlib.Path) -> dict:
    period = 2.0 / ticks
    study = (DATA / "SampledEstimate.mop").read_text()
    study = study.replace("extends SampledLoop(", f"extends SampledLoop(T = {period!r}, ", 1)
    for name in ("SampledLoop.mo", "sampled_loop.csv"):
        shutil.copy(DATA / name, work / name)
    (work / "SampledEstimate.mop").write_text(study)
    env = dict(os.environ, XDG_CACHE_HOME=str(work / "cache"))
    subprocess.run([morun, str(work / "SampledEstimate.mop"), "-o", str(work / "out")], env=env,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    summary = json.loads((work / "out" / "summary.json").read_text())
    return {"phases": summary["events"]["phases"], "status": summary["status"],
            "compile": summary["timings_seconds"].get("compile", float("nan")),
            "solve": summary["timings_seconds"].get("solve", float("nan")),
            "iterations": summary["iterations"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--morun", default=str(ROOT / "build" / "tools" / "morun"))
    ap.add_argument("ticks", nargs="*", type=int, default=[10, 100, 200, 500, 1000])
    args = ap.parse_args()
    print("| ticks | phases | compile s | solve s | iterations | status |")
    print("|---:|---:|---:|---:|---:|---|")
    for n in args.ticks:
        with tempfile.TemporaryDirectory() as tmp:
            r = run(args.morun, n, pathlib.Path(tmp))
        print(f"| {n} | {r['phases']} | {r['compile']:.2f} | {r['solve']:.2f} | {r['iterations']} | {r['status']} |",
              flush=True)


if __name__ == "__main__":
    main()
