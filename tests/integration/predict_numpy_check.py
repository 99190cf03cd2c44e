#!/usr/bin/env python3
"""An independent check of `demsa predict` (numpy and scipy only; nothing of demsa's code).

Usage:
  predict_numpy_check.py generate DIR        writes DIR/data.csv (160 training points) and DIR/points.csv
                                             (10,000 test points), physical units, fixed seed
  predict_numpy_check.py check DIR MODEL [SET]
                                             compares DIR/SET/pred_MODEL.csv (written by `demsa predict`) with an
                                             implementation of MODEL built here, from DIR/data.csv for the RSMs
                                             and RBFs, from the saved hyperparameters and training data of
                                             DIR/SET/y.MODEL.json for the GP (SET: models, the default, or
                                             models-nugget); exits 1 beyond the tolerance

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
# The GP without a nugget: its correlation matrix has a condition number of about 1e12 on this data (printed), and
# two double-precision solutions of it differ by several 1e-9 (numpy in double against long double: 4.3e-9). demsa
# refines its weights with residuals in long double and `demsa predict` sums k(x)ᵀα in long double (sobol/gp.hpp):
# 6e-10 from the long-double reference, held to TOLERANCE like every other model. The standard deviation is the
# square root of a difference that cancels, and the process variance comes from the weights: looser bounds there.
# With an estimated nugget (at least 1e-8) the problem is well conditioned.
GP_TOLERANCES = {"models": {"prediction": TOLERANCE, "sd": 1e-5, "variance": 1e-6},
                 "models-nugget": {"prediction": TOLERANCE, "sd": 1e-7, "variance": TOLERANCE}}
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
        return np.exp(-r2 / 2)
    r = np.sqrt(5 * r2)  # Matern 5/2 (Rasmussen & Williams 2006, eq. 4.17)
    return (1 + r + r * r / 3) * np.exp(-r)


def squared_distances(a, b):
    return ((a[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)


def cholesky(a):
    """Lower Cholesky factor, column by column, in the dtype of a (long double here: LAPACK has none)."""
    n = a.shape[0]
    lower = np.zeros_like(a)
    for j in range(n):
        lower[j, j] = np.sqrt(a[j, j] - lower[j, :j] @ lower[j, :j])
        lower[j + 1:, j] = (a[j + 1:, j] - lower[j + 1:, :j] @ lower[j, :j]) / lower[j, j]
    return lower


def cholesky_solve(lower, b):
    y = np.zeros_like(b)
    for i in range(lower.shape[0]):
        y[i] = (b[i] - lower[i, :i] @ y[:i]) / lower[i, i]
    x = np.zeros_like(b)
    for i in range(lower.shape[0] - 1, -1, -1):
        x[i] = (y[i] - lower[i + 1:, i] @ x[i + 1:]) / lower[i, i]
    return x


def gp_predict(model, unit_points, dtype):
    """Kriging rebuilt from the saved kernel, trend, length scales, nugget, jitter and training data, in `dtype`.

    The correlation matrix of a smooth kernel is ill-conditioned (about 1e12 here), so two double-precision solutions
    differ by about 1e-9 in their predictions; the reference is solved in long double (64-bit mantissa), where the
    rounding of the solve is 2000 times smaller. The scaled inputs u/theta and the correlations are formed in double,
    as demsa forms them: a different rounding of them is a different problem at this conditioning, and the reference
    is the exact solution of the problem demsa's numbers define."""
    g = model["gp"]
    x = np.array(model["training"]["unit_inputs"], dtype=float)
    y = np.array(model["training"]["outputs"], dtype=float).astype(dtype)
    inverse_lengths = 1.0 / np.array(g["lengths"], dtype=float)
    n = x.shape[0]
    xs, ps = x * inverse_lengths, unit_points * inverse_lengths
    r = kernel(g["kernel"], squared_distances(xs, xs))
    np.fill_diagonal(r, 1.0 + g["nugget"] + g["jitter"])
    r = r.astype(dtype)
    f = np.ones((n, 1), dtype=dtype)
    fp = np.ones((ps.shape[0], 1), dtype=dtype)
    if g["trend"] == "linear":
        f = np.column_stack([f, x.astype(dtype)])
        fp = np.column_stack([fp, unit_points.astype(dtype)])
    lower = cholesky(r)
    rinv_f = cholesky_solve(lower, f)
    ftrf = f.T @ rinv_f
    # beta from the small trend system (1 or d + 1 unknowns) in double, then one refinement step in dtype
    beta = np.linalg.solve(ftrf.astype(float), (rinv_f.T @ y).astype(float)).astype(dtype)
    beta = beta + np.linalg.solve(ftrf.astype(float), (rinv_f.T @ (y - f @ beta)).astype(float)).astype(dtype)
    alpha = cholesky_solve(lower, y - f @ beta)
    sigma2 = (y - f @ beta) @ alpha / n
    cross = kernel(g["kernel"], squared_distances(ps, xs)).astype(dtype)
    mean = fp @ beta + cross @ alpha
    quad = np.einsum("ij,ji->i", cross, cholesky_solve(lower, cross.T))
    sd = np.sqrt(np.maximum(sigma2 * (dtype(1.0) + dtype(g["nugget"]) - quad), dtype(0.0)))
    return mean.astype(float), sd.astype(float), float(sigma2)


def relative_error(got, want):
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


def check(directory, name, models="models"):
    header, data = read_csv(f"{directory}/data.csv")
    x, y = data[:, :3], data[:, 3]
    u = to_unit(x)
    with open(f"{directory}/{models}/y.{name}.json") as f:
        model = json.load(f)
    assert model["kind"] == name, model["kind"]
    saved_u = np.array(model["training"]["unit_inputs"], dtype=float)
    assert np.max(np.abs(saved_u - u)) < 1e-14, "the saved unit-cube inputs are not those of data.csv"
    pred_header, pred = read_csv(f"{directory}/{models}/pred_{name}.csv")
    assert pred_header[:4] == ["a", "b", "c", "y"], pred_header
    _, points = read_csv(f"{directory}/points.csv")
    tp = np.column_stack([points[:, 2], points[:, 3], points[:, 0]])
    assert np.array_equal(pred[:, :3], tp), "the predicted points are not those of points.csv"
    tu = to_unit(tp)
    failures = []
    tolerance = TOLERANCE
    if name.startswith("rsm"):
        p = int(name[3:])
        coefficients = np.linalg.lstsq(rsm_basis(u, p), y, rcond=None)[0]
        want = rsm_basis(tu, p) @ coefficients
    elif name.startswith("rbf"):
        interpolant = RBFInterpolator(u, y, kernel="cubic" if name == "rbf-cubic" else "thin_plate_spline",
                                      degree=1, smoothing=0.0)
        want = interpolant(tu)
    else:
        limits = GP_TOLERANCES[models]
        tolerance = limits["prediction"]
        g = model["gp"]
        xs = saved_u / np.array(g["lengths"])
        r = kernel(g["kernel"], squared_distances(xs, xs)) + (g["nugget"] + g["jitter"]) * np.eye(len(xs))
        print(f"gp ({models}): nugget {g['nugget']:.3g}, condition number of R {np.linalg.cond(r):.3g}")
        want64, _, _ = gp_predict(model, tu, np.float64)
        want, sd, sigma2 = gp_predict(model, tu, np.longdouble)
        print(f"gp: numpy in double against numpy in long double: {relative_error(want64, want):.3g}")
        e = relative_error(pred[:, 4], sd)
        print(f"gp: predictive sd, max |demsa - numpy| / max |numpy| = {e:.3g} (tolerance {limits['sd']:.0e})")
        if not e <= limits["sd"]:
            failures.append(f"sd {e:.3g}")
        s = abs(sigma2 - g["process_variance"]) / sigma2
        print(f"gp: process variance {g['process_variance']:.17g} saved, {sigma2:.17g} here ({s:.3g}, tolerance "
              f"{limits['variance']:.0e})")
        if not s <= limits["variance"]:
            failures.append(f"process variance {s:.3g}")
    e = relative_error(pred[:, 3], want)
    print(f"{name}: {len(want)} points, max |demsa - numpy/scipy| / max |numpy/scipy| = {e:.3g} (tolerance "
          f"{tolerance:.0e})")
    if not e <= tolerance:
        failures.append(f"prediction {e:.3g}")
    if failures:
        print(f"{name}: beyond the tolerance: {', '.join(failures)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "generate":
        generate(sys.argv[2])
        sys.exit(0)
    if len(sys.argv) in (4, 5) and sys.argv[1] == "check":
        sys.exit(check(*sys.argv[2:]))
    print(__doc__, file=sys.stderr)
    sys.exit(2)
