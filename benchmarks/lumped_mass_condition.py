#!/usr/bin/env python3
"""Spectrum of the lumped-mass-preconditioned consistent mass, D^{-1} M, on a
uniform 1D mesh of 30 elements (numpy), for Q2 Lagrange with HRZ lumping and
for C1 quadratic / C2 cubic B-splines with row-sum lumping; the 2D tensor
product squares the condition number (kappa_2D = kappa_1D^2). This bounds
how fast a lumped-mass-preconditioned CG or Chebyshev solve of the consistent
mass can be (doc/performance.md).
usage: python3 benchmarks/lumped_mass_condition.py"""
import numpy as np
from numpy.polynomial.legendre import leggauss


def lagrange_q2(n_elements):
    element = np.array([[4, 2, -1], [2, 16, 2], [-1, 2, 4]]) / 30.
    hrz = np.diag(element) * element.sum() / np.diag(element).sum()
    n = 2 * n_elements + 1
    mass, lumped = np.zeros((n, n)), np.zeros(n)
    for e in range(n_elements):
        dofs = [2 * e, 2 * e + 1, 2 * e + 2]
        mass[np.ix_(dofs, dofs)] += element
        lumped[dofs] += hrz
    return mass, lumped


def bspline(p, n_elements):
    knots = np.concatenate([np.zeros(p), np.arange(n_elements + 1), np.full(p, n_elements)]).astype(float)

    def basis(x):
        values = np.array([1.0 if knots[i] <= x < knots[i + 1] else 0.0 for i in range(len(knots) - 1)])
        for k in range(1, p + 1):
            new = np.zeros(len(knots) - 1 - k)
            for i in range(len(new)):
                a = 0 if knots[i + k] == knots[i] else (x - knots[i]) / (knots[i + k] - knots[i]) * values[i]
                b = 0 if knots[i + k + 1] == knots[i + 1] else \
                    (knots[i + k + 1] - x) / (knots[i + k + 1] - knots[i + 1]) * values[i + 1]
                new[i] = a + b
            values = new
        return values
    n = len(knots) - p - 1
    mass = np.zeros((n, n))
    points, weights = leggauss(p + 2)
    for e in range(n_elements):
        for xi, w in zip(points, weights):
            values = basis(e + 0.5 * (xi + 1))
            mass += 0.5 * w * np.outer(values, values)
    return mass, mass.sum(axis=1)


print("| element | lumping | lambda_min | lambda_max | kappa 1D | kappa 2D |")
print("|---|---|---|---|---|---|")
for name, lumping, (mass, lumped) in [("Q2 Lagrange", "HRZ", lagrange_q2(30)),
                                      ("B-spline p2 (C1)", "row-sum", bspline(2, 30)),
                                      ("B-spline p3 (C2)", "row-sum", bspline(3, 30))]:
    eigenvalues = np.linalg.eigvals(mass / lumped[:, None]).real
    kappa = eigenvalues.max() / eigenvalues.min()
    print(f"| {name} | {lumping} | {eigenvalues.min():.4f} | {eigenvalues.max():.4f} | {kappa:.2f} | {kappa ** 2:.1f} |")
