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

usage: /usr/bin/python3 bench/saltelli_pipeline.py DEMSA [N=16384] [RUNS=5] [BOOTSTRAP=200]
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


def demsa_once(demsa, n, bootstrap, work):
    design, y = os.path.join(work, "design.csv"), os.path.join(work, "y.csv")
    p = "-3.141592653589793:3.141592653589793"
    t0 = time.perf_counter()
    run([demsa, "design", "saltelli", "-N", str(n), "--param", "x1:" + p, "--param", "x2:" + p, "--param",
         "x3:" + p, "-o", design], stdout=subprocess.DEVNULL)
    t1 = time.perf_counter()
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
    demsa = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 16384
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    bootstrap = int(sys.argv[4]) if len(sys.argv) > 4 else 200
    load_before = open("/proc/loadavg").read().split()[:3]
    parts, ot_times = [], []
    with tempfile.TemporaryDirectory() as work:
        for _ in range(runs):
            parts.append(demsa_once(demsa, n, bootstrap, work))
            ot_times.append(openturns_once(n, bootstrap))
    load_after = open("/proc/loadavg").read().split()[:3]
    med = [statistics.median(p[k] for p in parts) for k in range(4)]
    ot_med = statistics.median(ot_times)
    print(f"Ishigami, N = {n} ({n * 5} evaluations), bootstrap {bootstrap}, medians of {runs} alternating runs")
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
