#!/usr/bin/env python3
"""An independent check of `demsa predict` (numpy and scipy only; nothing of demsa's code).

Usage:
  predict_numpy_check.py generate DIR        writes DIR/data.csv (160 training points) and DIR/points.csv
                                             (10,000 test points), physical units, fixed seed
  predict_numpy_check.py check DIR MODEL     compares DIR/pred_MODEL.csv (written by `demsa predict`) with an
                                             implementation of MODEL built here, from DIR/data.csv for the RSMs
                                             and RBFs, from the saved hyperparameters and training data of
                                             DIR/models/y.MODEL.json for the GP; exits 1 beyond the tolerance

References: the RSM is least squares on the orthonormal shifted Legendre basis of total degree <= p (Sudret 2008),
solved by numpy.linalg.lstsq; the RBFs are scipy.interpolate.RBFInterpolator (cubic r^3 and thin plate r^2 log r,
a linear tail, no smoothing; demsa's r^2 log r^2 is twice that kernel and gives the same interpolant); the GP is
Kriging with a generalised-least-squares trend (Rasmussen & Williams 2006, eq. 2.41; Santner, Williams, Notz
2003, section 3.3), solved here by Cholesky from the saved length scales, nugget and jitter.
"""
import csv
import itertools
import json
import math
import sys

import numpy as np
from numpy.polynomial import legendre
from scipy.interpolate import RBFInterpolator
from scipy.linalg import cho_factor, cho_solve

TOLERANCE = 1e-9
# The inputs of the test problem: name, low, high, scale. The same bounds are given to `demsa sensitivity`.
INPUTS = [("a", 0.0, 2.0, "uniform"), ("b", -1.0, 1.0, "uniform"), ("c", 1.0, 100.0, "log")]


def response(a, b, c):
    return np.exp(0.5 * a) + b**3 - 2.0 * a * b + np.log10(c) * np.sin(3.0 * b)


def to_unit(x):
    u = np.empty_like(x)
    for k, (_, low, high, scale) in enumerate(INPUTS):
        if scale == "log":
            u[:, k] = np.log(x[:, k] / low) / np.log(high / low)
        else:
            u[:, k] = (x[:, k] - low) / (high - low)
    return u


def to_physical(u):
    x = np.empty_like(u)
    for k, (_, low, high, scale) in enumerate(INPUTS):
        x[:, k] = low * (high / low) ** u[:, k] if scale == "log" else low + u[:, k] * (high - low)
    return x


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([repr(float(v)) for v in r])


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header = [h.strip() for h in rows[0]]
    values = np.array([[float(v) for v in r] for r in rows[1:] if r], dtype=float)
    return header, values


def generate(directory):
    rng = np.random.default_rng(20261201)
    n, m, d = 160, 10000, len(INPUTS)
    # Training: a Latin hypercube on the unit cube (one point per stratum and input), then physical units.
    u = np.empty((n, d))
    for k in range(d):
        u[:, k] = (rng.permutation(n) + rng.uniform(size=n)) / n
    x = to_physical(u)
    y = response(x[:, 0], x[:, 1], x[:, 2])
    # A column demsa does not read (a label): the points file may hold other columns.
    write_csv(f"{directory}/data.csv", ["a", "b", "c", "y"], np.column_stack([x, y]))
    t = to_physical(rng.uniform(size=(m, d)))
    write_csv(f"{directory}/points.csv", ["c", "note", "a", "b"],
              np.column_stack([t[:, 2], np.arange(m), t[:, 0], t[:, 1]]))


def multi_indices(d, p):
    return [a for a in itertools.product(range(p + 1), repeat=d) if sum(a) <= p]


def legendre01(k, u):
    coefficients = np.zeros(k + 1)
    coefficients[k] = 1.0
    return math.sqrt(2 * k + 1) * legendre.legval(2.0 * u - 1.0, coefficients)


def rsm_basis(u, p):
    columns = []
    for alpha in multi_indices(u.shape[1], p):
        column = np.ones(u.shape[0])
        for k, a in enumerate(alpha):
            column = column * legendre01(a, u[:, k])
        columns.append(column)
    return np.column_stack(columns)


def kernel(name, r2):
    if name == "squared-exponential":
        return np.exp(-0.5 * r2)
    r = np.sqrt(5.0 * r2)  # Matern 5/2 (Rasmussen & Williams 2006, eq. 4.17)
    return (1.0 + r + r * r / 3.0) * np.exp(-r)


def squared_distances(a, b):
    return ((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)


def gp_predict(model, unit_points):
    g = model["gp"]
    x = np.array(model["training"]["unit_inputs"], dtype=float)
    y = np.array(model["training"]["outputs"], dtype=float)
    theta = np.array(g["lengths"], dtype=float)
    n = x.shape[0]
    xs, ps = x / theta, unit_points / theta
    r = kernel(g["kernel"], squared_distances(xs, xs))
    np.fill_diagonal(r, 1.0 + g["nugget"] + g["jitter"])
    f = np.ones((n, 1)) if g["trend"] == "constant" else np.column_stack([np.ones(n), x])
    fp = np.ones((ps.shape[0], 1)) if g["trend"] == "constant" else np.column_stack([np.ones(ps.shape[0]),
                                                                                      unit_points])
    factor = cho_factor(r, lower=True)
    rinv_f = cho_solve(factor, f)
    beta = np.linalg.solve(f.T @ rinv_f, rinv_f.T @ y)
    alpha = cho_solve(factor, y - f @ beta)
    sigma2 = (y - f @ beta) @ alpha / n
    cross = kernel(g["kernel"], squared_distances(ps, xs))
    mean = fp @ beta + cross @ alpha
    quad = np.einsum("ij,ji->i", cross, cho_solve(factor, cross.T))
    sd = np.sqrt(np.maximum(sigma2 * (1.0 + g["nugget"] - quad), 0.0))
    return mean, sd, sigma2


def relative_error(got, want):
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


def check(directory, name):
    header, data = read_csv(f"{directory}/data.csv")
    x, y = data[:, :3], data[:, 3]
    u = to_unit(x)
    with open(f"{directory}/models/y.{name}.json") as f:
        model = json.load(f)
    assert model["kind"] == name, model["kind"]
    saved_u = np.array(model["training"]["unit_inputs"], dtype=float)
    assert np.max(np.abs(saved_u - u)) < 1e-14, "the saved unit-cube inputs are not those of data.csv"
    pred_header, pred = read_csv(f"{directory}/pred_{name}.csv")
    assert pred_header[:4] == ["a", "b", "c", "y"], pred_header
    _, points = read_csv(f"{directory}/points.csv")
    tp = np.column_stack([points[:, 2], points[:, 3], points[:, 0]])
    assert np.array_equal(pred[:, :3], tp), "the predicted points are not those of points.csv"
    tu = to_unit(tp)
    failures = []
    if name.startswith("rsm"):
        p = int(name[3:])
        coefficients = np.linalg.lstsq(rsm_basis(u, p), y, rcond=None)[0]
        want = rsm_basis(tu, p) @ coefficients
    elif name.startswith("rbf"):
        interpolant = RBFInterpolator(u, y, kernel="cubic" if name == "rbf-cubic" else "thin_plate_spline",
                                      degree=1, smoothing=0.0)
        want = interpolant(tu)
    else:
        want, sd, sigma2 = gp_predict(model, tu)
        e = relative_error(pred[:, 4], sd)
        print(f"gp: predictive sd, max |demsa - numpy| / max |numpy| = {e:.3g}")
        if not e <= TOLERANCE:
            failures.append(f"sd {e:.3g}")
        s = abs(sigma2 - model["gp"]["process_variance"]) / sigma2
        print(f"gp: process variance {model['gp']['process_variance']:.17g} saved, {sigma2:.17g} here ({s:.3g})")
        if not s <= TOLERANCE:
            failures.append(f"process variance {s:.3g}")
    e = relative_error(pred[:, 3], want)
    print(f"{name}: {len(want)} points, max |demsa - numpy/scipy| / max |numpy/scipy| = {e:.3g}")
    if not e <= TOLERANCE:
        failures.append(f"prediction {e:.3g}")
    if failures:
        print(f"{name}: beyond {TOLERANCE}: {', '.join(failures)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "generate":
        generate(sys.argv[2])
        sys.exit(0)
    if len(sys.argv) == 4 and sys.argv[1] == "check":
        sys.exit(check(sys.argv[2], sys.argv[3]))
    print(__doc__, file=sys.stderr)
    sys.exit(2)
