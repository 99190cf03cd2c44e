#!/usr/bin/env python3
"""When a servo oedometer's load counts as reached (docs/explanation/experiments.md, "Oedometer").

Replays the servo rule of liggghts_templates/oedometer.liggghts on the plate histories of a finished servo study
(every case's plate_history.txt, a row every history interval): a load counts as reached at the first check
(servo_check_steps) whose mean plate force is within TOL of the load and whose plate speed over the check is below
REST. For each (TOL, REST) pair it prints the steps the study would have taken and how far the plate stood, at the
reached check of every load, from where the recorded run reached it (with its own, usually tighter, rule).

Usage: bench/oedometer-stopping.py STUDY_FOLDER [TOL:REST ...]
  e.g. bench/oedometer-stopping.py /tmp/oed/oedometer 0.03:1e-3 1:1e-3 1:1e-4 2:1e-4
Only the standard library; the replay is exact up to the alignment of the history rows with the checks.
"""
import json
import statistics
import sys
from pathlib import Path


def read_history(path):
    rows = []
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        step, load, z, force = (float(v) for v in line.split()[:4])
        rows.append((int(step), load, z, force))
    return rows


def read_states(path):
    states = {}
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        load, z, _force, converged = line.split()[:4]
        states[float(load)] = (float(z), converged == "1")
    return states


def replay(rows, load, tol, rest, dt, check_steps, history_steps):
    """The first check of `load` that the rule passes: (steps spent on the load, plate z), or None."""
    per_check = max(1, check_steps // history_steps)
    z_before = None
    own = [r for r in rows if r[1] == load]
    for end in range(per_check, len(own) + 1, per_check):
        block = own[end - per_check:end]
        force = statistics.fmean(r[3] for r in block)
        start_z = z_before if z_before is not None else block[0][2]
        speed = abs(block[-1][2] - start_z) / (check_steps * dt)
        z_before = block[-1][2]
        if abs(force - load) <= tol and speed < rest:
            return end * history_steps, block[-1][2]
    return None


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    study = Path(argv[1])
    rules = [tuple(float(v) for v in a.split(":")) for a in argv[2:]] or [(0.03, 1e-3), (1, 1e-3), (1, 1e-4)]
    cases = sorted(p for p in (study / "cases").iterdir() if (p / "plate_history.txt").exists())
    if not cases:
        print(f"{study}/cases: no case with a plate_history.txt", file=sys.stderr)
        return 2
    print(f"{study}: {len(cases)} cases")
    print(f"{'tol N':>7} {'rest m/s':>9} {'steps':>9} {'median/case':>12} {'max/case':>9} {'unreached':>9} "
          f"{'|dz| median um':>15} {'|dz| max um':>12}")
    for tol, rest in rules:
        totals, dzs, unreached = [], [], 0
        for case in cases:
            info = json.loads((case / "case.json").read_text())
            servo = info["oedometer"]["servo"]
            rows = read_history(case / "plate_history.txt")
            states = read_states(case / "plate_states.txt")
            history_steps = rows[1][0] - rows[0][0] if len(rows) > 1 else 1
            steps = 0
            for load in info["oedometer"]["loads_N"]:
                hit = replay(rows, load, tol, rest, info["dt"], servo["check_steps"], history_steps)
                if hit is None:
                    unreached += 1
                    steps += sum(1 for r in rows if r[1] == load) * history_steps
                    continue
                steps += hit[0]
                z_run, converged = states.get(load, (None, False))
                if converged:
                    dzs.append(abs(hit[1] - z_run) * 1e6)
            totals.append(steps)
        print(f"{tol:7g} {rest:9g} {sum(totals):9.3g} {statistics.median(totals):12.3g} {max(totals):9.3g} "
              f"{unreached:9d} {statistics.median(dzs) if dzs else float('nan'):15.1f} "
              f"{max(dzs) if dzs else float('nan'):12.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
