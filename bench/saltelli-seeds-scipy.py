#!/usr/bin/python3
"""The comparison row of docs/explanation/benchmarks.md ("Accuracy of the QMC estimators"): Ishigami on second-order Saltelli
designs built from SciPy's scrambled Sobol' sequence (A and B = the two halves of one 6-D sequence), with Saltelli
2010's S1 and Jansen's ST averaged over A and B exchanged and the variance of A and B. Seeds 1..100.

usage: bench/saltelli-seeds-scipy.py [BASE]   (needs Debian's python3-scipy; default base 2048)
"""
import sys

import numpy as np
from scipy.stats import qmc

S1 = np.array([0.313905, 0.442411, 0.0])
ST = np.array([0.557589, 0.442411, 0.243684])


def ishigami(u):
    x = -np.pi + 2 * np.pi * u
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


base = int(sys.argv[1]) if len(sys.argv) > 1 else 2048
squares, worst, within, seeds = 0.0, 0.0, 0, range(1, 101)
for seed in seeds:
    x = qmc.Sobol(6, scramble=True, seed=seed).random(base)
    a_in, b_in = x[:, :3], x[:, 3:]
    a, b = ishigami(a_in), ishigami(b_in)
    v = np.concatenate([a, b]).var()
    errors = []
    for i in range(3):
        ab_in, ba_in = a_in.copy(), b_in.copy()
        ab_in[:, i], ba_in[:, i] = b_in[:, i], a_in[:, i]
        ab, ba = ishigami(ab_in), ishigami(ba_in)
        s1 = 0.5 * (np.mean(b * (ab - a)) + np.mean(a * (ba - b))) / v
        st = 0.25 * (np.mean((a - ab) ** 2) + np.mean((b - ba) ** 2)) / v
        errors += [s1 - S1[i], st - ST[i]]
    errors = np.abs(errors)
    squares += float((errors ** 2).sum())
    worst = max(worst, float(errors.max()))
    within += int(errors.max() <= 0.005)
print(f"SciPy Sobol', base {base}, {len(seeds)} seeds: RMS error of S1/ST {np.sqrt(squares / (6 * len(seeds))):.5f}, "
      f"worst seed {worst:.4f}, {within} seeds with max |error| <= 0.005")
