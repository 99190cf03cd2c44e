#!/usr/bin/env python3
"""What a servo oedometer load costs, from finished studies (docs/how-to/cost.md, "The servo oedometer's model").

For every case of each STUDY_FOLDER (its cases/*/plate_history.txt, case.json and the store's case_costs) it prints a
row per case: its parameters, its time step, and each load's steps, simulated time (steps x dt) and plate travel. Then
the correlations of each load's log steps and log simulated time with the parameters (log E for E), and the model of
orchestrator/experiments/oedometer/cost.cpp fitted on the first study and checked on the others: a load's steps are
T / dt, with T the ratio estimator sum(steps) / sum(1 / dt) of the fitting study's loads (at most the cap), and the
study's expected atom-steps against its actual. Cases that did not finish (not `done` in the store) are listed and left
out of the totals.

Usage: bench/oedometer-load-times.py FIT_STUDY CHECK_STUDY [...]
  e.g. bench/oedometer-load-times.py /tmp/oed-noise/oedometer-noise /tmp/oed2/oedometer
Only the standard library.
"""
import json
import math
import sqlite3
import statistics
import sys
from pathlib import Path

PARAMETERS = ["E", "nu", "mu_pp", "mu_pw", "e_r", "mu_r_pp", "mu_r_pw"]


def done_samples(study):
    with sqlite3.connect(f"file:{study / 'study.db'}?mode=ro", uri=True) as db:
        return {s for (s,) in db.execute("SELECT sample FROM runs WHERE state = 'done'")}


def loads_of(history):
    """[(load, steps, travel_m)] from plate_history.txt: the steps between the first rows of consecutive loads."""
    rows = []
    for line in history.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        step, load, z = line.split()[:3]
        rows.append((int(step), float(load), float(z)))
    loads, start, z0 = [], rows[0][0], rows[0][2]
    for (s0, l0, zz0), (s1, l1, zz1) in zip(rows, rows[1:]):
        if l1 != l0:
            loads.append((l0, s0 - start, z0 - zz0))
            start, z0 = s0, zz0
    loads.append((rows[-1][1], rows[-1][0] - start, z0 - rows[-1][2]))
    return loads


def read_study(study):
    study = Path(study)
    done = done_samples(study)
    cases = []
    for folder in sorted((study / "cases").iterdir()):
        history = folder / "plate_history.txt"
        if not history.exists():
            continue
        doc = json.loads((folder / "case.json").read_text())
        oed = doc["oedometer"]
        cap = -(-oed["servo"]["max_steps"] // oed["servo"]["check_steps"]) * oed["servo"]["check_steps"]
        cases.append({"sample": doc["sample"], "done": doc["sample"] in done, "p": doc["parameters"], "dt": doc["dt"],
                      "fill": oed["fill_steps"], "atoms": doc["assembly"]["particles"], "cap": cap,
                      "loads": loads_of(history)})
    return study, cases


def atom_steps(c):
    return (c["fill"] + sum(steps for _, steps, _ in c["loads"])) * c["atoms"]


def expected(c, seconds):
    return (c["fill"] + sum(min(c["cap"], seconds / c["dt"]) for _ in c["loads"])) * c["atoms"]


def table(study, cases):
    print(f"\n{study}: {len(cases)} cases")
    print("sample done   E[Pa]    nu  mu_pp mu_pw  e_r mu_r_pp mu_r_pw  dt[s]     "
          "load: steps / simulated s / travel mm ...  atom-steps")
    for c in cases:
        p = c["p"]
        loads = "  ".join(f"{load:g} N: {steps} / {steps * c['dt']:.2f} / {travel * 1e3:.2f}"
                          for load, steps, travel in c["loads"])
        print(f"{c['sample']:6d} {'yes' if c['done'] else 'no ':4s} {p['E']:.3g} {p['nu']:.2f} {p['mu_pp']:5.2f} "
              f"{p['mu_pw']:5.2f} {p['e_r']:.2f} {p['mu_r_pp']:7.2f} {p['mu_r_pw']:7.2f} {c['dt']:.3g}  {loads}  "
              f"{atom_steps(c):.3g}")


def correlations(cases):
    n_loads = min(len(c["loads"]) for c in cases)
    for k in range(n_loads):
        steps = [math.log(c["loads"][k][1]) for c in cases]
        time = [math.log(c["loads"][k][1] * c["dt"]) for c in cases]
        xs = {name: [math.log(c["p"][name]) if name == "E" else c["p"][name] for c in cases] for name in PARAMETERS}
        print(f"load {k + 1}: corr(log steps, .) " +
              " ".join(f"{n}={statistics.correlation(x, steps):+.2f}" for n, x in xs.items()))
        print(f"        corr(log time, .)  " +
              " ".join(f"{n}={statistics.correlation(x, time):+.2f}" for n, x in xs.items()))
        print(f"        simulated time: mean {statistics.mean(math.exp(t) for t in time):.2f} s, "
              f"range {math.exp(min(time)):.2f}-{math.exp(max(time)):.2f} s")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    studies = [read_study(s) for s in sys.argv[1:]]
    for study, cases in studies:
        table(study, cases)
    every = [c for _, cases in studies for c in cases if c["done"]]
    print(f"\ncorrelations over the {len(every)} finished cases of all studies:")
    correlations(every)
    fit = [c for c in studies[0][1] if c["done"]]
    seconds = sum(s for c in fit for _, s, _ in c["loads"]) / sum(len(c["loads"]) / c["dt"] for c in fit)
    mean = statistics.mean(s * c["dt"] for c in fit for _, s, _ in c["loads"])
    print(f"\nfitted on {studies[0][0]}: T = {seconds:.3f} s a load (ratio estimator; plain mean {mean:.3f} s)")
    for study, cases in studies:
        finished = [c for c in cases if c["done"]]
        e = sum(expected(c, seconds) for c in finished)
        a = sum(atom_steps(c) for c in finished)
        ratios = [atom_steps(c) / expected(c, seconds) for c in finished]
        print(f"{study}: {len(finished)} finished cases, expected {e:.3g} atom-steps, actual {a:.3g}, "
              f"expected / actual {e / a:.2f}; one case's actual / expected {min(ratios):.2f}-{max(ratios):.2f}; "
              f"all {len(cases)} cases expected {sum(expected(c, seconds) for c in cases):.3g}")


if __name__ == "__main__":
    main()
