#!/usr/bin/python3
"""OpenTURNS side of the 160 x 7 maximin LHS benchmark (docs/explanation/benchmarks.md, section "Reproducible designs").

Usage: /usr/bin/python3 bench/lhs-maximin-openturns.py [ITERATIONS] [COOLING] [FIRST_SEED] [LAST_SEED]

For each seed: ot.SimulatedAnnealingLHS with the SpaceFillingMinDist criterion and a geometric temperature profile
(T0 = 10, c = COOLING, ITERATIONS steps at most; OpenTURNS's default is c = 0.95, 2000 steps) on an LHSExperiment with random positions inside
the strata (as demsa's lhs-maximin), and the minimum distance on the unit cube. Prints one line per seed and the
median CPU time, the worst and mean minimum distance.
"""
import statistics
import sys
import time

import openturns as ot

iterations = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
cooling = float(sys.argv[2]) if len(sys.argv) > 2 else 0.95
first = int(sys.argv[3]) if len(sys.argv) > 3 else 1
last = int(sys.argv[4]) if len(sys.argv) > 4 else 20
n, d = 160, 7
ot.Log.Show(ot.Log.NONE)
distribution = ot.JointDistribution([ot.Uniform(0.0, 1.0)] * d) if hasattr(ot, "JointDistribution") else \
    ot.ComposedDistribution([ot.Uniform(0.0, 1.0)] * d)
distances, times = [], []
for seed in range(first, last + 1):
    ot.RandomGenerator.SetSeed(seed)
    lhs = ot.LHSExperiment(distribution, n, False, True)  # alwaysShuffle = False, randomShift = True
    algo = ot.SimulatedAnnealingLHS(lhs, ot.SpaceFillingMinDist(), ot.GeometricProfile(10.0, cooling, iterations))
    start = time.process_time()
    design = algo.generate()
    seconds = time.process_time() - start
    dist = ot.SpaceFillingMinDist().evaluate(design)  # the minimum distance (OpenTURNS 1.20)
    print(f"seed {seed:2d}  min distance {dist:.4f}  cpu {seconds:.2f} s", flush=True)
    distances.append(dist)
    times.append(seconds)
print(f"ITERATIONS {iterations} COOLING {cooling}: worst {min(distances):.4f} mean {statistics.mean(distances):.4f} "
      f"median cpu {statistics.median(times):.2f} s")
