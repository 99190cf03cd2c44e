#!/usr/bin/python3
"""The Saltelli pipeline of Ishigami at base N, demsa against OpenTURNS, side by side (docs/benchmarks.md,
"Saltelli pipeline against OpenTURNS").

demsa: `demsa design saltelli` writes the design CSV, awk evaluates Ishigami on every row (the simulator, outside
demsa), `demsa sensitivity --saltelli` reads both files and computes S1, ST and their intervals.
OpenTURNS 1.20: SobolIndicesExperiment on an unscrambled Sobol' sequence (LowDiscrepancyExperiment), the model
evaluated in memory, SaltelliSensitivityAlgorithm with BOOTSTRAP bootstrap intervals (none when 0), all inside one
Python process; its time is taken inside that process, after `import openturns`. demsa runs with the same
--bootstrap.

Runs alternate (demsa, OpenTURNS, demsa, ...) so that both see the same load; medians of RUNS runs.

usage: /usr/bin/python3 bench/saltelli_pipeline.py DEMSA [N=16384] [RUNS=5] [BOOTSTRAP=200] [--design-once]

--design-once writes the design once (timed once) and times the evaluation and `demsa sensitivity` on every run:
for measuring the analysis while the design command is being changed.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

AWK_ISHIGAMI = r"""
BEGIN { FS = ","; print "y" }
NR == 1 { for (k = 1; k <= NF; ++k) col[$k] = k; next }
{ x1 = $col["x1"]; x2 = $col["x2"]; x3 = $col["x3"]; s = sin(x2);
  printf "%.17g\n", sin(x1) + 7 * s * s + 0.1 * x3 * x3 * x3 * x3 * sin(x1) }
"""

OPENTURNS = r"""
import sys, time
import openturns as ot
n, bootstrap = int(sys.argv[1]), int(sys.argv[2])
start = time.perf_counter()
if bootstrap > 0:
    ot.ResourceMap.SetAsUnsignedInteger("SobolIndicesAlgorithm-DefaultBootstrapSize", bootstrap)
model = ot.SymbolicFunction(["x1", "x2", "x3"], ["sin(x1) + 7 * sin(x2)^2 + 0.1 * x3^4 * sin(x1)"])
distribution = ot.ComposedDistribution([ot.Uniform(-3.141592653589793, 3.141592653589793)] * 3)
experiment = ot.LowDiscrepancyExperiment(ot.SobolSequence(), distribution, n, False)
x = ot.SobolIndicesExperiment(experiment, False).generate()
y = model(x)
algorithm = ot.SaltelliSensitivityAlgorithm(x, y, n)
s1, st = algorithm.getFirstOrderIndices(), algorithm.getTotalOrderIndices()
if bootstrap > 0:
    i1, it = algorithm.getFirstOrderIndicesInterval(), algorithm.getTotalOrderIndicesInterval()
print(time.perf_counter() - start)
print(" ".join(f"{v:.4f}" for v in list(s1) + list(st)), file=sys.stderr)
"""


def run(argv, **kw):
    subprocess.run(argv, check=True, **kw)


def write_design(demsa, n, design):
    p = "-3.141592653589793:3.141592653589793"
    t0 = time.perf_counter()
    run([demsa, "design", "saltelli", "-N", str(n), "--param", "x1:" + p, "--param", "x2:" + p, "--param",
         "x3:" + p, "-o", design], stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def demsa_once(demsa, n, bootstrap, work, design_seconds=None):
    design, y = os.path.join(work, "design.csv"), os.path.join(work, "y.csv")
    t0 = time.perf_counter()
    if design_seconds is None:
        write_design(demsa, n, design)
    t1 = time.perf_counter()
    if design_seconds is not None:
        t0 = t1 - design_seconds
    with open(design) as fin, open(y, "w") as fout:
        run(["awk", AWK_ISHIGAMI], stdin=fin, stdout=fout)
    t2 = time.perf_counter()
    run([demsa, "sensitivity", "--saltelli", design, "--responses", y, "--bootstrap", str(bootstrap)],
        stdout=subprocess.DEVNULL)
    t3 = time.perf_counter()
    return t1 - t0, t2 - t1, t3 - t2, t3 - t0


def openturns_once(n, bootstrap):
    out = subprocess.run(["/usr/bin/python3", "-c", OPENTURNS, str(n), str(bootstrap)], check=True,
                         capture_output=True, text=True)
    return float(out.stdout.strip())


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    design_once = "--design-once" in sys.argv
    args = [a for a in sys.argv[1:] if a != "--design-once"]
    demsa = args[0]
    n = int(args[1]) if len(args) > 1 else 16384
    runs = int(args[2]) if len(args) > 2 else 5
    bootstrap = int(args[3]) if len(args) > 3 else 200
    load_before = open("/proc/loadavg").read().split()[:3]
    parts, ot_times = [], []
    with tempfile.TemporaryDirectory() as work:
        design_seconds = write_design(demsa, n, os.path.join(work, "design.csv")) if design_once else None
        for _ in range(runs):
            parts.append(demsa_once(demsa, n, bootstrap, work, design_seconds))
            ot_times.append(openturns_once(n, bootstrap))
    load_after = open("/proc/loadavg").read().split()[:3]
    med = [statistics.median(p[k] for p in parts) for k in range(4)]
    ot_med = statistics.median(ot_times)
    print(f"Ishigami, N = {n} ({n * 5} evaluations), bootstrap {bootstrap}, medians of {runs} alternating runs"
          + (" (design written once, its time counted in every run)" if design_once else ""))
    print(f"load average before {' '.join(load_before)}, after {' '.join(load_after)}")
    print("| step | demsa [s] | OpenTURNS 1.20 [s] |")
    print("|---|---|---|")
    print(f"| design | {med[0]:.3f} | |")
    print(f"| Ishigami on every row (awk, outside demsa) | {med[1]:.3f} | |")
    print(f"| sensitivity --saltelli (read CSVs, S1, ST, intervals) | {med[2]:.3f} | |")
    print(f"| whole pipeline | {med[3]:.3f} | {ot_med:.3f} |")
    print(f"ratio demsa / OpenTURNS, whole pipeline: {med[3] / ot_med:.2f}; demsa without the awk evaluation: "
          f"{(med[3] - med[1]) / ot_med:.2f}")


if __name__ == "__main__":
    main()
