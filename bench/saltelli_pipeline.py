#!/usr/bin/python3
"""The Saltelli pipeline of Ishigami at base N, demsa against OpenTURNS, side by side (docs/explanation/benchmarks.md,
"Saltelli pipeline against OpenTURNS").

demsa: `demsa design saltelli` writes the design CSV, awk evaluates Ishigami on every row (the simulator, outside
demsa), `demsa sensitivity --saltelli` reads both files and computes S1, ST and their intervals.
OpenTURNS 1.20: SobolIndicesExperiment on an unscrambled Sobol' sequence (LowDiscrepancyExperiment), the model
evaluated in memory, SaltelliSensitivityAlgorithm with BOOTSTRAP bootstrap intervals (none when 0), all inside one
Python process; its time is taken inside that process, after `import openturns`. demsa runs with the same
--bootstrap.

Runs alternate (demsa, OpenTURNS, demsa, ...) so that both see the same load; medians of RUNS runs. Wall-clock
times, and CPU times (user + system: of the child processes for demsa and awk, from getrusage, dynamic loading
included; `time.process_time` inside the OpenTURNS process), which a loaded machine inflates much less.

usage: /usr/bin/python3 bench/saltelli_pipeline.py DEMSA [N=16384] [RUNS=5] [BOOTSTRAP=200] [--design-once]
           [--evaluator awk|compiled]

--evaluator compiled evaluates Ishigami with bench/ishigami_eval (built beside demsa in BUILD/bench/), as a compiled
simulator would, instead of awk (the default).

--design-once writes the design once (timed once) and times the evaluation and `demsa sensitivity` on every run:
for measuring the analysis while the design command is being changed.
"""
import os
import resource
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
start, cpu = time.perf_counter(), time.process_time()
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
print(time.perf_counter() - start, time.process_time() - cpu)
print(" ".join(f"{v:.4f}" for v in list(s1) + list(st)), file=sys.stderr)
"""


def run(argv, **kw):
    subprocess.run(argv, check=True, **kw)


def write_design(demsa, n, design):
    p = "-3.141592653589793:3.141592653589793"
    t0 = time.perf_counter()
    # One design, as OpenTURNS draws it (demsa's default is 8 replicates, for its Student-t intervals).
    run([demsa, "design", "saltelli", "-N", str(n), "--param", "x1:" + p, "--param", "x2:" + p, "--param",
         "x3:" + p, "--replicates", "1", "-o", design], stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def demsa_once(demsa, n, bootstrap, work, evaluator, design_seconds=None):
    """(design, awk, sensitivity, whole) wall times and the same CPU times of one demsa pipeline."""
    design, y = os.path.join(work, "design.csv"), os.path.join(work, "y.csv")
    c0, t0 = children_cpu(), time.perf_counter()
    if design_seconds is None:
        write_design(demsa, n, design)
    c1, t1 = children_cpu(), time.perf_counter()
    if design_seconds is not None:
        t0, c0 = t1 - design_seconds[0], c1 - design_seconds[1]
    with open(design) as fin, open(y, "w") as fout:
        run(evaluator, stdin=fin, stdout=fout)
    c2, t2 = children_cpu(), time.perf_counter()
    run([demsa, "sensitivity", "--saltelli", design, "--responses", y, "--bootstrap", str(bootstrap)],
        stdout=subprocess.DEVNULL)
    c3, t3 = children_cpu(), time.perf_counter()
    return (t1 - t0, t2 - t1, t3 - t2, t3 - t0), (c1 - c0, c2 - c1, c3 - c2, c3 - c0)


def openturns_once(n, bootstrap):
    """Wall and CPU time of OpenTURNS's pipeline, inside its process after the import."""
    out = subprocess.run(["/usr/bin/python3", "-c", OPENTURNS, str(n), str(bootstrap)], check=True,
                         capture_output=True, text=True)
    wall, cpu = out.stdout.split()
    return float(wall), float(cpu)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    design_once = "--design-once" in sys.argv
    args = [a for a in sys.argv[1:] if a != "--design-once"]
    evaluator_name = "awk"
    if "--evaluator" in args:
        k = args.index("--evaluator")
        if k + 1 >= len(args) or args[k + 1] not in ("awk", "compiled"):
            sys.exit("--evaluator takes awk or compiled")
        evaluator_name = args[k + 1]
        del args[k:k + 2]
    demsa = args[0]
    evaluator = ["awk", AWK_ISHIGAMI]
    if evaluator_name == "compiled":
        compiled = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(demsa))), "bench", "ishigami_eval")
        if not os.access(compiled, os.X_OK):
            sys.exit(f"{compiled} not found: build the bench target ishigami_eval")
        evaluator = [compiled]
    n = int(args[1]) if len(args) > 1 else 16384
    runs = int(args[2]) if len(args) > 2 else 5
    bootstrap = int(args[3]) if len(args) > 3 else 200
    load_before = open("/proc/loadavg").read().split()[:3]
    walls, cpus, ot_walls, ot_cpus = [], [], [], []
    with tempfile.TemporaryDirectory() as work:
        design_seconds = None
        if design_once:
            c0 = children_cpu()
            wall = write_design(demsa, n, os.path.join(work, "design.csv"))
            design_seconds = (wall, children_cpu() - c0)
        for _ in range(runs):
            wall, cpu = demsa_once(demsa, n, bootstrap, work, evaluator, design_seconds)
            walls.append(wall)
            cpus.append(cpu)
            wall, cpu = openturns_once(n, bootstrap)
            ot_walls.append(wall)
            ot_cpus.append(cpu)
    load_after = open("/proc/loadavg").read().split()[:3]
    med = [statistics.median(p[k] for p in walls) for k in range(4)]
    cmed = [statistics.median(p[k] for p in cpus) for k in range(4)]
    ot_med, ot_cmed = statistics.median(ot_walls), statistics.median(ot_cpus)
    print(f"Ishigami, N = {n} ({n * 5} evaluations), bootstrap {bootstrap}, medians of {runs} alternating runs"
          + (" (design written once, its time counted in every run)" if design_once else ""))
    print(f"load average before {' '.join(load_before)}, after {' '.join(load_after)}")
    print("| step | demsa wall [s] | demsa CPU [s] | OpenTURNS 1.20 wall [s] | OpenTURNS CPU [s] |")
    print("|---|---|---|---|---|")
    print(f"| design | {med[0]:.3f} | {cmed[0]:.3f} | | |")
    print(f"| Ishigami on every row ({evaluator_name}, outside demsa) | {med[1]:.3f} | {cmed[1]:.3f} | | |")
    print(f"| sensitivity --saltelli (read CSVs, S1, ST, intervals) | {med[2]:.3f} | {cmed[2]:.3f} | | |")
    print(f"| whole pipeline | {med[3]:.3f} | {cmed[3]:.3f} | {ot_med:.3f} | {ot_cmed:.3f} |")
    print(f"ratio demsa / OpenTURNS, whole pipeline: wall {med[3] / ot_med:.2f}, CPU {cmed[3] / ot_cmed:.2f}; "
          f"demsa without the {evaluator_name} evaluation: wall {(med[3] - med[1]) / ot_med:.2f}, "
          f"CPU {(cmed[3] - cmed[1]) / ot_cmed:.2f}")


if __name__ == "__main__":
    main()
