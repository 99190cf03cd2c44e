#!/usr/bin/env python3
"""The angles of two settings of the same cases, per design point (docs/explanation/benchmarks.md).

Usage: bench/paired_angles.py WORK IDS OLD NEW
  WORK: the folder of bench/liggghts-builds.sh (its runs OLD-K and NEW-K, each with angle.txt and cpu.txt);
  IDS: the case ids, comma-separated, three packings of each design point in a row.
Prints, per design point, the angles of the three packings with each setting and the paired differences NEW − OLD;
the packing noise of each (the pooled within-point standard deviation); the mean difference and its standard
error; and the CPU-seconds of the two (their total ratio and the median of the per-case ratios).
"""
import math
import statistics
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    work, ids, old, new = sys.argv[1], sys.argv[2].split(","), sys.argv[3], sys.argv[4]
    angle = lambda name, k: float(open(f"{work}/{name}-{k}/angle.txt").read())
    cpu = lambda name, k: sum(map(float, open(f"{work}/{name}-{k}/cpu.txt").read().split()[-2:]))
    points = [ids[i:i + 3] for i in range(0, len(ids), 3)]
    print(f"| design point | {old} [deg] (3 packings) | {new} [deg] | {new} − {old} per packing | mean {new} − {old} |")
    print("|---|---|---|---|---|")
    ss = {old: 0.0, new: 0.0}
    diffs = []
    for p, ks in enumerate(points):
        a = {n: [angle(n, k) for k in ks] for n in (old, new)}
        for n in a:
            m = statistics.mean(a[n])
            ss[n] += sum((x - m) ** 2 for x in a[n])
        d = [y - x for x, y in zip(a[old], a[new])]
        diffs += d
        f = lambda v: ", ".join(f"{x:.2f}" for x in v)
        print(f"| {p} | {f(a[old])} | {f(a[new])} | {', '.join(f'{x:+.2f}' for x in d)} | {statistics.mean(d):+.2f} |")
    dof = len(ids) - len(points)
    for n in ss:
        print(f"packing noise, {n}: pooled sd {math.sqrt(ss[n] / dof):.2f} deg ({dof} degrees of freedom)")
    md, sd = statistics.mean(diffs), statistics.stdev(diffs)
    print(f"{new} − {old} over the {len(diffs)} cases: mean {md:+.2f} deg, sd {sd:.2f} deg, "
          f"standard error {sd / math.sqrt(len(diffs)):.2f} deg")
    mo = [statistics.mean([angle(old, k) for k in ks]) for ks in points]
    mn = [statistics.mean([angle(new, k) for k in ks]) for ks in points]
    print(f"per-point means {new} − {old}:", ", ".join(f"{b - a:+.2f}" for a, b in zip(mo, mn)))
    co, cn = [cpu(old, k) for k in ids], [cpu(new, k) for k in ids]
    print(f"CPU-s: {old} {sum(co):.1f}, {new} {sum(cn):.1f}: {old} / {new} = {sum(co) / sum(cn):.3f} in all, "
          f"median per case {statistics.median(o / n for o, n in zip(co, cn)):.3f} "
          f"({min(o / n for o, n in zip(co, cn)):.3f}-{max(o / n for o, n in zip(co, cn)):.3f})")


if __name__ == "__main__":
    main()
