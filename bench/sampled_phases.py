#!/usr/bin/env python3
"""How a study's cost grows with the sample ticks of a sampled-data model.

Each tick that changes the model is a phase of the multi-phase collocation
(docs/events.md, "Sampled-data models"). This runs, with the sample period T
set so that the 2 s horizon has N ticks:

- the estimation of tests/e2e/data/SampledEstimate.mop (a first-order plant
  under a sampled proportional controller, 20 samples);
- the D-optimal design of tests/e2e/data/SampledDesign.mop (the same loop's
  set point designed for a and b), N measurements, one on each tick;

and prints per N the phases, morun's compile and solve seconds (summary.json's
timings) and Ipopt's iterations.

Usage: bench/sampled_phases.py [--morun build/tools/morun] [--study estimation|design|both] [N ...]
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


def estimation(ticks: int, work: pathlib.Path) -> list:
    period = 2.0 / ticks
    study = (DATA / "SampledEstimate.mop").read_text()
    study = study.replace("extends SampledLoop(", f"extends SampledLoop(T = {period!r}, ", 1)
    for name in ("SampledLoop.mo", "sampled_loop.csv"):
        shutil.copy(DATA / name, work / name)
    (work / "SampledEstimate.mop").write_text(study)
    return [str(work / "SampledEstimate.mop")]


def design(ticks: int, work: pathlib.Path) -> list:
    shutil.copy(DATA / "SampledDesign.mop", work / "SampledDesign.mop")
    return [str(work / "SampledDesign.mop"), "--set", f"T={2.0 / ticks!r}", "--option", f"measurements={ticks}"]


def run(morun: str, args: list, work: pathlib.Path) -> dict:
    env = dict(os.environ, XDG_CACHE_HOME=str(work / "cache"))
    subprocess.run([morun, *args, "-o", str(work / "out")], env=env,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    summary = json.loads((work / "out" / "summary.json").read_text())
    return {"phases": summary["events"]["phases"], "status": summary["status"],
            "compile": summary["timings_seconds"].get("compile", float("nan")),
            "solve": summary["timings_seconds"].get("solve", float("nan")),
            "iterations": summary["iterations"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--morun", default=str(ROOT / "build" / "tools" / "morun"))
    ap.add_argument("--study", choices=["estimation", "design", "both"], default="both")
    ap.add_argument("ticks", nargs="*", type=int, default=[10, 100, 200, 500, 1000])
    args = ap.parse_args()
    studies = {"estimation": estimation, "design": design}
    for name in ["estimation", "design"] if args.study == "both" else [args.study]:
        print(f"\n{name}:\n")
        print("| ticks | phases | compile s | solve s | iterations | status |")
        print("|---:|---:|---:|---:|---:|---|")
        for n in args.ticks:
            with tempfile.TemporaryDirectory() as tmp:
                work = pathlib.Path(tmp)
                r = run(args.morun, studies[name](n, work), work)
            print(f"| {n} | {r['phases']} | {r['compile']:.2f} | {r['solve']:.2f} | {r['iterations']} | {r['status']} |",
                  flush=True)


if __name__ == "__main__":
    main()
