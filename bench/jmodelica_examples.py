#!/usr/bin/env python3
"""JModelica's Optimica examples run with morun (issue 12).

The examples in JModelica's Python/src/pyjmi/examples that solve an
`optimization` class and assert the optimum, run on the example's own files
with its options translated to `--option`; each is checked against the value
the example asserts. JModelica's files are read from a checkout given as an
argument (they are not part of mocompile):

    bench/jmodelica_examples.py JMODELICA_DIR [--morun build/tools/morun] [--msl MSL_DIR]
                                [--only NAME...] [--timeout SECONDS]

Prints one line per example: `reached`, `missed` (solved, other optimum),
`failed` (morun's first error) or `not run` (what the example needs that has
no morun translation), then the count that reach JModelica's optimum.
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib

FILES = "Python/src/pyjmi/examples/files"

# name, study file, libraries, class, --option list, checks, or a reason not to run;
# msl: the example uses the Modelica Standard Library (given with --msl);
# simulate: (class, stop time) simulated first with morun, as the example does
# for its init_traj, its result directory given to the options as {simulation};
# prepare: the name of a function in PREPARE that runs the example's own
# Python steps before the solve (as morun simulations, or data files written
# here) and returns the --set values and options they give, and None or a
# study (file, class) to solve instead of the example's class (which is then
# loaded as a library).
# A check is (what, expected, rtol, atol): what is "objective", "final_time",
# "final:<column of trajectories.csv>", "parameter:<free parameter>" or
# "information" (design: the criterion JModelica minimises is -trace F).
EXAMPLES = [
    dict(name="vdp_casadi", file="VDP.mop", cls="VDP_pack.VDP_Opt2", options=["n_e=30"],
         checks=[("final:x1", 0.0, 0, 1e-3), ("final:x2", 0.0, 0, 1e-3)]),
    dict(name="vdp_minimum_time_casadi", msl=True, file="JMExamples_opt.mop", libs=["JMExamples.mo"],
         cls="JMExamples_opt.VDP_Opt_Min_Time", options=[],
         checks=[("final_time", 2.2811587, 0, 1e-3)]),
    dict(name="cstr_casadi", msl=True, file="CSTR.mop", cls="CSTR.CSTR_Opt2",
         options=["n_e=19", "tol=1e-10", "piecewise_constant_controls=false"],
         prepare="cstr_chain",
         note="the example's Python steps as morun runs: CSTR_Init's stationary points at Tc = 250 and 280, "
              "then CSTR_Init_Optimization simulated from A towards B for init_result; their values --set",
         checks=[("objective", 1.86162353098e3, 0, 1.0)]),
    dict(name="ccpp", msl=True, file="CombinedCycleStartup.mop", libs=["CombinedCycle.mo"],
         cls="CombinedCycleStartup.Startup6", options=["n_e=50", 'init_result="{simulation}/result.csv"'],
         simulate=("CombinedCycleStartup.Startup6Reference", 10000),
         note="init_traj and nominal_traj: a simulation of Startup6Reference to 10000 s, as the example",
         checks=[("objective", 17492.465548193624, 1e-5, 0)]),
    dict(name="ccpp_elimination", msl=True, file="CombinedCycleStartup.mop", libs=["CombinedCycle.mo"],
         cls="CombinedCycleStartup.Startup6", options=["n_e=50", 'init_result="{simulation}/result.csv"'],
         simulate=("CombinedCycleStartup.Startup6Reference", 10000),
         note="init_traj and nominal_traj: a simulation of Startup6Reference to 10000 s, as the example",
         checks=[("objective", 17492.465548193624, 1e-5, 0)]),
    dict(name="ccpp_sym_elim", msl=True, file="CombinedCycleStartup.mop", libs=["CombinedCycle.mo"],
         cls="CombinedCycleStartup.Startup6", options=["n_e=50", 'init_result="{simulation}/result.csv"'],
         simulate=("CombinedCycleStartup.Startup6Reference", 10000),
         note="init_traj and nominal_traj: a simulation of Startup6Reference to 10000 s, as the example",
         checks=[("objective", 17492.465548193624, 1e-5, 0)]),
    dict(name="distillation4_opt", msl=True, file="JMExamples_opt.mop", libs=["JMExamples.mo"],
         cls="JMExamples_opt.Distillation4_Opt", options=["n_e=15", 'ipopt_options={"mu_init=1e-3"}'],
         checks=[("objective", 4.611038777467e-02, 1e-2, 0)]),
    dict(name="double_pendulum", msl=True, file="DoublePendulum.mop", libs=["DoublePendulum.mo"], cls="DoublePendulum.Opt",
         options=["n_e=100", 'init_result="{simulation}/result.csv"', "piecewise_constant_controls=false"],
         simulate=("DoublePendulum.Feedback", 3),
         note="init_traj and nominal_traj: a simulation of Feedback (the linear state feedback) to 3 s, as the "
              "example; JModelica's inputs without blocking factors take a value per collocation point",
         checks=[("objective", 9.632883808252522, 5e-3, 0)]),
    dict(name="elimination_example", file="JMExamples_opt.mop", cls="JMExamples_opt.EliminationExample",
         options=["piecewise_constant_controls=false"],
         note="JModelica's inputs without blocking factors take a value per collocation point", checks=[("objective", 1.0818134, 1e-4, 0)]),
    dict(name="fed_batch_oed", file="fed_batch_reactor.mop", cls="FedBatchReactor_OED",
         options=["task=design", "criterion=T", "parameters={theta1,theta2,theta3,theta4}",
                  "outputs={y1,y2}", "sigma={0.31622776601683794}",
                  "measurement_times={2,4,6,8,10,12,14,16,18,20}", "n_e=30",
                  "blocking_factors={3,3,3,3,3,3,3,3,3,3}"],
         checks=[("objective", -1.311920e+07, 1e-3, 0)],
         note="setup_oed's sigma = diag(10, 10) weighs the Fisher matrix (F = sum S' sigma S, "
              "100 times F with sigma as a covariance), so sigma = 1/sqrt(10) in morun's terms"),
    dict(name="fourbar1", msl=True, file="Fourbar1.mop", libs=["Fourbar1.mo"], cls="Fourbar1.Opt",
         options=["n_e=20", "piecewise_constant_controls=false"],
         note="from the default start: the example's init_traj, a simulation of Fourbar1Sim under the torque of "
              "fourbar1_init.txt, is not made (that file itself as the guess leads to another optimum, 0.119); "
              "an input value per collocation point, as JModelica's",
         checks=[("objective", 1.0455646e-03, 5e-3, 0)]),
    dict(name="vehicle_turn", msl=True, file="vehicle_turn.mop", cls="Turn",
         options=["n_e=60", "tol=1e-9",
                  "blocking_factors={%s}" % ", ".join(
                      '"%s=%s"' % (u, ",".join([str(f)] * (60 // f)))
                      for u, f in (("delta_u", 2), ("Twf_u", 4), ("Twr_u", 4))),
                  # the example's du_bounds: 2 / rad2deg with its rad2deg = 180/(2 pi)
                  'du_bounds={"delta_u=%.17g"}' % (2.0 / (180.0 / (2 * math.pi))),
                  "init_result=\"{files}/vehicle_turn_dymola.txt\""],
         checks=[("final_time", 4.0118, 5e-3, 0)],
         note="blocking_factors per input, du_bounds and the Dymola result as initial guess, "
              "as the example sets them"),
    dict(name="qt_par_est_casadi", msl=True, file="QuadTankPack.mop", cls="QuadTankPack.QuadTank_ParEstCasADi",
         options=["n_e=60", "piecewise_constant_controls=false"], prepare="quad_tank_data",
         note="the example's Python as the runner's: qt_par_est_data.mat rows 6000::100, t - 60, levels / 100; "
              "ExternalData quad_pen (x1, x2 weight 1, u1, u2 weight 10) as a wrapper class extending "
              "QuadTank_ParEstCasADi with objectiveIntegrand = sum of Q (v - v_data)^2 and the data as given "
              "inputs (study option inputs); init_result a simulation of QuadTank under the measured inputs",
         checks=[("parameter:a1", 0.02656702e-4, 1e-4, 0), ("parameter:a2", 0.02713898e-4, 1e-4, 0)]),
    dict(name="cstr_mpc_casadi", skip="model-predictive control: a loop of shifted solves driven by "
         "Python, not one study"),
    dict(name="greybox_identification", skip="grey-box identification driven by Python "
         "(pyjmi.optimization.greybox), not one study"),
]


def first_row(out, names):
    """The values of columns `names` in the first row of `out`/result.csv."""
    rows = list(csv.reader(open(os.path.join(out, "result.csv"))))
    return [float(rows[1][rows[0].index(n)]) for n in names]


def cstr_chain(simulate, scratch, files):
    """cstr_casadi's Python before its solve: the stationary points A (Tc = 250)
    and B (Tc = 280) of CSTR_Init (initial equations der(c) = der(T) = 0 at
    the input's value), then CSTR_Init_Optimization simulated for 150 s from
    A with B's values as references: its result is the initial guess (the
    example's init_traj and nominal_traj). Returns the --set values of
    CSTR_Opt2 and the options."""
    point = {}
    for name, tc in (("A", 250), ("B", 280)):
        out = os.path.join(scratch, "cstr-init-" + name)
        simulate("CSTR.CSTR_Init", out, ["--input", f"Tc=const:{tc}", "--stop-time", "1", "--intervals", "1"])
        point[name] = [tc] + first_row(out, ["c", "T"])
    (_, c_a, t_a), (tc_b, c_b, t_b) = point["A"], point["B"]
    sets = [f"cstr.c_init={c_a!r}", f"cstr.T_init={t_a!r}", f"c_ref={c_b!r}", f"T_ref={t_b!r}", f"Tc_ref={tc_b!r}"]
    guess = os.path.join(scratch, "cstr-init-trajectory")
    args = ["--stop-time", "150", "--intervals", "1000"]
    for v in sets:
        args += ["--set", v]
    simulate("CSTR.CSTR_Init_Optimization", guess, args)
    return sets, [f'init_result="{guess}/result.csv"'], None


MAT_TYPES = {1: "b", 2: "B", 3: "h", 4: "H", 5: "i", 6: "I", 7: "f", 9: "d", 12: "q", 13: "Q"}


def mat5_elements(buf, pos, end, endian):
    """(type, bytes) of the MAT v5 data elements in buf[pos:end]."""
    while pos < end:
        typ, nbytes = struct.unpack_from(endian + "II", buf, pos)
        if typ >> 16:  # a small element: its size in the upper half, its data in the next 4 bytes
            yield typ & 0xFFFF, buf[pos + 4:pos + 4 + (typ >> 16)]
            pos += 8
            continue
        yield typ, buf[pos + 8:pos + 8 + nbytes]
        pos += 8 + nbytes + (0 if typ == 15 else -nbytes % 8)


def read_mat5(path):
    """The real numeric matrices of a MATLAB v5 file: name -> (dims, values in column order)."""
    buf = open(path, "rb").read()
    endian = "<" if buf[126:128] == b"IM" else ">"
    out, pending = {}, list(mat5_elements(buf, 128, len(buf), endian))
    while pending:
        typ, data = pending.pop(0)
        if typ == 15:  # compressed: the elements inside
            inner = zlib.decompress(data)
            pending[0:0] = list(mat5_elements(inner, 0, len(inner), endian))
            continue
        parts = list(mat5_elements(data, 0, len(data), endian)) if typ == 14 else []
        numbers = [list(struct.unpack(endian + MAT_TYPES[t] * (len(d) // struct.calcsize(MAT_TYPES[t])), d))
                   for t, d in parts[:2] + parts[3:4] if t in MAT_TYPES]
        if len(numbers) == 3 and 6 <= numbers[0][0] & 0xFF <= 15 and not numbers[0][0] & 0x800:  # numeric, real
            out[parts[2][1].decode()] = (numbers[1], numbers[2])
    return out


def external_data_study(path, base, penalties):
    """An optimization class extending `base` whose objectiveIntegrand is
    JModelica's ExternalData quad_pen with a diagonal Q: the sum of
    weight * (v - v_data)^2 over (v, weight) in `penalties`, v_data an input
    that study option inputs gives the data."""
    terms = " + ".join(f"{w!r} * ({v} - {v}_data)^2" for v, w in penalties)
    inputs = ", ".join(f"{v}_data" for v, _ in penalties)
    with open(path, "w") as f:
        f.write(f"optimization ExternalData(objectiveIntegrand = {terms})\n  extends {base};\n"
                f"  input Real {inputs};\nend ExternalData;\n")
    return path, "ExternalData"


def quad_tank_data(simulate, scratch, files):
    """qt_par_est_casadi's Python before its solve: the measurements of
    qt_par_est_data.mat from row 6000 in steps of 100 (t - 60, levels / 100
    from cm to m), a simulation of QuadTank from the problem's initial levels
    under the measured inputs (the example's init_traj and nominal_traj), and
    ExternalData(Q = diag(1, 1, 10, 10), quad_pen = x1, x2, u1, u2)."""
    mat = read_mat5(os.path.join(files, "qt_par_est_data.mat"))
    col = {name: values for name, (dims, values) in mat.items()}
    rows = range(6000, len(col["t"]), 100)
    series = {"x1": [col["y1_f"][k] / 100 for k in rows], "x2": [col["y2_f"][k] / 100 for k in rows],
              "u1": [col["u1_d"][k] for k in rows], "u2": [col["u2_d"][k] for k in rows]}
    times = [col["t"][k] - 60 for k in rows]
    data = os.path.join(scratch, "quad-tank-data.csv")
    with open(data, "w") as f:
        f.write("time," + ",".join(f"{v}_data,{v}" for v in series) + "\n")
        for k, t in enumerate(times):
            f.write(f"{t!r}," + ",".join(f"{series[v][k]!r},{series[v][k]!r}" for v in series) + "\n")
    levels = ["x1_0=0.06255", "x2_0=0.06045", "x3_0=0.02395", "x4_0=0.02325"]  # QuadTank_ParEstCasADi's
    guess = os.path.join(scratch, "quad-tank-simulation")
    args = ["--stop-time", "60", "--intervals", "600", "--input", f"u1=csv:{data}", "--input", f"u2=csv:{data}"]
    for v in levels:
        args += ["--set", v]
    simulate("QuadTankPack.QuadTank", guess, args)
    given = ";".join(f"{v}_data=csv:{data}" for v in series)
    study = external_data_study(os.path.join(scratch, "QuadTankExternalData.mop"),
                                "QuadTankPack.QuadTank_ParEstCasADi", [("x1", 1), ("x2", 1), ("u1", 10), ("u2", 10)])
    return [], [f'inputs={{"{given}"}}', f'init_result="{guess}/result.csv"'], study


PREPARE = {"cstr_chain": cstr_chain, "quad_tank_data": quad_tank_data}


class StepFailed(Exception):
    pass


def value(what, out):
    """The quantity `what` of the study results in `out`."""
    s = json.load(open(os.path.join(out, "summary.json")))
    if what == "objective":
        return s["objective"]
    if what == "final_time":
        return s.get("final_time", s["horizon"][1])
    if what.startswith("parameter:"):
        return s["parameters"][what[10:]]
    if what.startswith("final:"):
        rows = list(csv.reader(open(os.path.join(out, "trajectories.csv"))))
        return float(rows[-1][rows[0].index(what[6:])])
    raise ValueError(what)


def first_error(text):
    for line in text.splitlines():
        if "error" in line:
            return line.strip()
    lines = [l for l in text.splitlines() if l.strip()]
    return lines[-1].strip() if lines else "no output"


def run(example, files, morun, scratch, msl, timeout):
    if "skip" in example:
        return "not run", example["skip"]
    out = os.path.join(scratch, example["name"])
    cmd = [morun, os.path.join(files, example["file"]), "--class", example["cls"], "-o", out]
    for lib in example.get("libs", []):
        cmd += ["-L", os.path.join(files, lib)]
    if example.get("msl") and msl:
        cmd += ["-L", os.path.join(msl, "Modelica")]
        services = os.path.join(msl, "ModelicaServices")  # MultiBody's animation shapes extend it
        if os.path.isdir(services):
            cmd += ["-L", services]
    sim_dir = os.path.join(scratch, example["name"] + "-simulation")
    if "simulate" in example:
        cls, stop = example["simulate"]
        libraries = cmd[6:]  # the -L arguments
        sim = [morun, os.path.join(files, example["file"]), "--class", cls, "-o", sim_dir,
               "--stop-time", str(stop), "--intervals", "1000", "--quiet"] + libraries
        try:
            p = subprocess.run(sim, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return "failed", f"the simulation of {cls} stopped after the time limit of {timeout} s"
        if p.returncode != 0:
            return "failed", f"the simulation of {cls}: " + first_error(p.stderr)
    options = list(example["options"])
    if "prepare" in example:
        def simulate(cls, out_dir, args):
            step = [morun, os.path.join(files, example["file"]), "--class", cls, "-o", out_dir, "--quiet"]
            step += cmd[6:] + args  # the -L arguments
            try:
                q = subprocess.run(step, capture_output=True, text=True, timeout=timeout)
            except subprocess.TimeoutExpired:
                raise StepFailed(f"the simulation of {cls} stopped after the time limit of {timeout} s")
            if q.returncode != 0:
                raise StepFailed(f"the simulation of {cls}: " + first_error(q.stderr))
        try:
            sets, extra, study = PREPARE[example["prepare"]](simulate, scratch, files)
        except StepFailed as e:
            return "failed", str(e)
        if study:  # solved instead of the example's class, which it extends
            cmd += ["-L", cmd[1]]
            cmd[1], cmd[3] = study
        for v in sets:
            cmd += ["--set", v]
        options += extra
    for opt in ["plot=false"] + options:
        cmd += ["--option", opt.replace("{files}", files).replace("{simulation}", sim_dir)]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "failed", f"stopped after the time limit of {timeout} s (--timeout)"
    if not os.path.exists(os.path.join(out, "summary.json")):
        return "failed", first_error(p.stderr)
    got = []
    ok = p.returncode == 0
    for what, expected, rtol, atol in example["checks"]:
        v = value(what, out)
        got.append(f"{what} = {v:.8g} (JModelica {expected:.8g})")
        ok = ok and abs(v - expected) <= atol + rtol * abs(expected)
    status = json.load(open(os.path.join(out, "summary.json"))).get("status", "?")
    return ("reached" if ok else "missed"), f"{status}; " + ", ".join(got)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("jmodelica", help="a checkout of github.com/JModelica/JModelica")
    ap.add_argument("--morun", default=os.path.join(os.path.dirname(__file__), "..", "build", "tools", "morun"))
    ap.add_argument("--only", nargs="*", help="run only these examples")
    ap.add_argument("--timeout", type=float, default=600, help="seconds per example (default 600)")
    ap.add_argument("--msl", help="the Modelica Standard Library 3.2.2 (a directory holding Modelica/), "
                    "for the examples that use it (marked msl)")
    args = ap.parse_args()
    files = os.path.join(args.jmodelica, FILES)
    if not os.path.isdir(files):
        sys.exit(f"{files}: not a directory (give the JModelica checkout)")
    reached = 0
    with tempfile.TemporaryDirectory(prefix="jmodelica-examples-") as scratch:
        for ex in EXAMPLES:
            if args.only and ex["name"] not in args.only:
                continue
            status, detail = run(ex, files, os.path.abspath(args.morun), scratch, args.msl, args.timeout)
            reached += status == "reached"
            note = f" [{ex['note']}]" if "note" in ex else ""
            print(f"{ex['name']:26s} {status:8s} {detail}{note}", flush=True)
    print(f"reached JModelica's optimum: {reached} of {len(EXAMPLES)}")


if __name__ == "__main__":
    main()
