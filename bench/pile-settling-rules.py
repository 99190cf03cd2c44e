#!/usr/bin/env python3
"""Which settling rule stops a pile once its angle has stopped moving (docs/explanation/science.md, "The settling
verdict and the quickstart").

Replays the speed criterion of liggghts_templates/pile.liggghts on a pile study whose cases settled to their cap
with a snapshot at every settling check (`settle_window` longer than `settle_time`, `history_interval` =
`settle_check_time`: bench/pile-settling-rules.toml is the quickstart so). For every rule (the share `settle_quantile`
of the particles on the pedestal slower than the case's speed limit, at `settle_window` consecutive checks, the
cap `settle_time`) it prints how many cases demsa would flag (the criterion not met by the cap, or the angle's
drift at the stop above `drift_limit`: the Theil-Sen slope over the snapshots of the last `drift_window`, taken
every SNAP checks as the study's `history_interval` would), the study's atom-steps against the first rule's, and
how far the angle at the stop lies from the angle at the cap.

Usage: bench/pile-settling-rules.py STUDY_FOLDER [--snap K] [--drift-window S] [--drift-limit D]
                                    [QUANTILE:WINDOW_CHECKS:CAP_CHECKS ...]
  e.g. bench/pile-settling-rules.py /tmp/settling/pile-settling-rules --snap 10 0.95:5:60 0.98:20:100 0.99:10:100
Only the standard library.
"""
import argparse
import csv
import math
import re
import statistics
import sys
from pathlib import Path

LOOP = re.compile(r"Loop time of \S+ on \d+ procs for (\d+) steps with (\d+) atoms")


def theil_sen(points):
    """Theil, Indagationes Math. 12 (1950); Sen, JASA 63 (1968): the median of the pairwise slopes."""
    slopes = [(b[1] - a[1]) / (b[0] - a[0]) for i, a in enumerate(points) for b in points[i + 1:] if b[0] > a[0]]
    return statistics.median(slopes) if slopes else float("nan")


def load_case(folder):
    settling = dict(line.split(None, 1) for line in (folder / "pile_settling.txt").read_text().splitlines() if line)
    start, check_steps = int(settling["start_step"]), int(settling["check_steps"])
    limit = float(settling["speed_limit"])
    history = {}
    with open(folder / "pile_history.csv") as f:
        for row in csv.DictReader(line for line in f if not line.startswith("#")):
            if int(row["check"]) >= 0:
                history[int(row["check"])] = (float(row["time_s"]), float(row["angle_deg"]), int(row["on_pedestal"]))
    log = (folder / "log.liggghts").read_text()
    checks = {}  # settling check -> (atoms, fastest on the pedestal, particles faster than the limit on it)
    for line in log.splitlines():
        fields = line.split()
        if len(fields) != 8:
            continue
        try:
            values = [float(v) for v in fields]
        except ValueError:
            continue
        step = int(values[0])
        if step > start and (step - start) % check_steps == 0:
            checks[(step - start) // check_steps] = (int(values[1]), values[5], int(values[6]))
    total = sum(int(s) * int(a) for s, a in LOOP.findall(log))
    return {"history": history, "checks": checks, "limit": limit, "check_steps": check_steps, "total": total}


def stop_check(case, quantile, window, cap):
    calm = 0
    for k in range(1, cap + 1):
        if k not in case["checks"] or k not in case["history"]:
            return k - 1, False
        _atoms, fastest, fast = case["checks"][k]
        allowed = math.floor((1 - quantile) * case["history"][k][2])
        calm = calm + 1 if (fastest <= case["limit"] if quantile >= 1 else fast <= allowed) else 0
        if calm >= window:
            return k, True
    return cap, False


def drift(case, k, snap, window_s):
    t_end = case["history"][k][0]
    points = sorted((t, a) for c, (t, a, _n) in case["history"].items()
                    if c <= k and (c % snap == 0 or c == k) and t >= t_end - window_s - 1e-9 and not math.isnan(a))
    return theil_sen(points)


def settling_atom_steps(case, k):
    return sum(case["checks"][c][0] for c in range(1, k + 1) if c in case["checks"]) * case["check_steps"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study")
    parser.add_argument("rules", nargs="*", default=["0.95:5:60", "0.98:20:100", "0.99:10:100"])
    parser.add_argument("--snap", type=int, default=10, help="checks between snapshots (default 10)")
    parser.add_argument("--drift-window", type=float, default=0.2)
    parser.add_argument("--drift-limit", type=float, default=1.0)
    args = parser.parse_args()
    folders = sorted(p for p in (Path(args.study) / "cases").iterdir() if (p / "pile_settling.txt").exists())
    if not folders:
        print(f"{args.study}/cases: no finished pile case", file=sys.stderr)
        return 2
    cases = [load_case(f) for f in folders]
    print(f"{args.study}: {len(cases)} cases; drift over {args.drift_window} s of snapshots every {args.snap} checks, "
          f"limit {args.drift_limit} deg/s")
    print(f"{'quantile':>8} {'window':>6} {'cap':>4} {'flagged':>7} {'atom-steps':>10} {'ratio':>6} "
          f"{'angle(cap)-angle(stop) mean':>28} {'max':>6}")
    first = None
    for rule in args.rules:
        quantile, window, cap = (float(v) for v in rule.split(":"))
        window, cap = int(window), int(cap)
        flagged, cost, moves = 0, 0, []
        for case in cases:
            last = max(case["history"])
            k, criterion = stop_check(case, quantile, window, min(cap, last))
            if not criterion or abs(drift(case, k, args.snap, args.drift_window)) > args.drift_limit:
                flagged += 1
            cost += case["total"] - settling_atom_steps(case, last) + settling_atom_steps(case, k)
            moves.append(case["history"][last][1] - case["history"][k][1])
        first = first or cost
        print(f"{quantile:8g} {window:6d} {cap:4d} {flagged:7d} {cost:10.3g} {cost / first:6.2f} "
              f"{statistics.fmean(moves):+28.2f} {max(moves):+6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
