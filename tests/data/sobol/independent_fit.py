#!/usr/bin/python3
"""Independent reference fits for demsa's metamodel tests (numpy least squares, scipy RBFInterpolator).

usage: independent_fit.py KIND TRAIN.csv QUERY.csv OUT.csv
  KIND: rsm1|rsm2|rsm3 (monomials of total degree <= p, numpy.linalg.lstsq), rbf-cubic (scipy kernel 'cubic'),
        rbf-tps (scipy kernel 'thin_plate_spline'; r² log r is half of r² log r², the same interpolant).
  TRAIN.csv: header, columns x1..xd then y. QUERY.csv: header, columns x1..xd. OUT.csv: one prediction per line.
"""
import itertools
import sys

import numpy as np


def monomials(x, degree):
    n, d = x.shape
    cols = [np.ones(n)]
    for p in range(1, degree + 1):
        for combo in itertools.combinations_with_replacement(range(d), p):
            cols.append(np.prod(x[:, combo], axis=1))
    return np.column_stack(cols)


def main():
    kind, train, query, out = sys.argv[1:5]
    t = np.loadtxt(train, delimiter=",", skiprows=1, ndmin=2)
    q = np.loadtxt(query, delimiter=",", skiprows=1, ndmin=2)
    x, y = t[:, :-1], t[:, -1]
    if kind.startswith("rsm"):
        degree = int(kind[3:])
        coef, *_ = np.linalg.lstsq(monomials(x, degree), y, rcond=None)
        pred = monomials(q, degree) @ coef
    else:
        from scipy.interpolate import RBFInterpolator
        kernel = {"rbf-cubic": "cubic", "rbf-tps": "thin_plate_spline"}[kind]
        pred = RBFInterpolator(x, y, kernel=kernel, degree=1)(q)
    np.savetxt(out, pred, fmt="%.17g")


if __name__ == "__main__":
    main()
