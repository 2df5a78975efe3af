"""The point field contact_pressure_Pa of the ParaView output (issue 11): on
the contact surface it is the consistent contact pressure. A run with a
pressure profile and a VTU output at the same step (t = 0.2 s, in contact);
at every Gauss point of the profile CSV (body 1 and body 2) the VTU field is
evaluated with VTK's own cell (higher-order cells: vtkLagrangeQuadrilateral
for FEA, vtkBezierQuadrilateral with its RationalWeights for IGA) at the
point of the cell's arc edge with the Gauss point's position across the
line of impact, and must equal the CSV's `pressure` to 1e-10 of the largest
pressure.

usage: vtu_contact_pressure.py ISOIMPACT PRM_DIR WORK_DIR"""
import csv
import os
import subprocess
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from testing import check_close, check_true, edit_prm, read_prm, report

program, prm_dir, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
EDGES = [lambda t: (t, 0., 0.), lambda t: (1., t, 0.), lambda t: (t, 1., 0.), lambda t: (0., t, 0.)]


def evaluate(cell, edge, t, field):
    """Position and field at parameter t of an edge of a VTK cell."""
    x, weights = [0., 0., 0.], [0.] * cell.GetNumberOfPoints()
    cell.EvaluateLocation(vtk.mutable(0), edge(t), x, weights)
    value = sum(w * field[cell.GetPointId(i)] for i, w in enumerate(weights))
    return np.array(x[:2]), value


def arc_edges(grid, center, radius, lower):
    """(cell, edge) of the arc's edges (each cell its own object: GetCell
    reuses one) on the side of the centre that faces
    the other body (y < centre for body 1, > for body 2)."""
    found = []
    for c in range(grid.GetNumberOfCells()):
        cell = vtk.vtkGenericCell()
        grid.GetCell(c, cell)
        for edge in EDGES:
            ends = [evaluate(cell, edge, t, np.zeros(grid.GetNumberOfPoints()))[0] for t in (0., 0.5, 1.)]
            on_arc = max(abs(np.linalg.norm(x - center) - radius) for x in ends) < 1e-9 * radius
            side = all((x[1] < center[1] + 1e-12) if lower else (x[1] > center[1] - 1e-12) for x in ends)
            if on_arc and side:
                found.append((cell, edge))
    return found


def field_at(edges, x_target, field):
    """The field at the point of the arc edges with x = x_target (x is
    monotonic along an arc edge of a quarter circle): bisection on t."""
    for cell, edge in edges:
        x0, x1 = evaluate(cell, edge, 0., field)[0][0], evaluate(cell, edge, 1., field)[0][0]
        if min(x0, x1) - 1e-14 <= x_target <= max(x0, x1) + 1e-14:
            a, b = 0., 1.
            for _ in range(60):
                m = 0.5 * (a + b)
                if (evaluate(cell, edge, m, field)[0][0] - x_target) * (x1 - x0) < 0.:
                    a = m
                else:
                    b = m
            return evaluate(cell, edge, 0.5 * (a + b), field)[1]
    return None


for name, prm in [("fea", "hertz_fea_hrz_coarse.prm"), ("iga", "hertz_iga_hrz_coarse.prm")]:
    folder = os.path.join(work, name)
    path = edit_prm(os.path.join(prm_dir, prm), os.path.join(work, name + ".prm"),
                    {"Output/Directory": folder, "Time integration/End time": "0.2",
                     "Time integration/Time step": "5e-4", "Output/VTU interval": "400",
                     "Output/VTU cells": "higher order", "Output/Pressure profile times": "0.2",
                     "Output/Progress interval": "100"})
    result = subprocess.run([program, path], capture_output=True, text=True)
    check_true(f"{name}: the run completes (exit {result.returncode})", result.returncode == 0)
    if result.returncode != 0:
        print(result.stdout[-2000:], result.stderr[-2000:])
        continue
    values = read_prm(path)
    rows = [r for r in csv.reader(l for l in open(os.path.join(folder, "contact_pressure_t0.2000.csv"))
                                  if not l.startswith("#"))]
    header, rows = rows[0], rows[1:]
    position, pressure, surface = (header.index(k) for k in ("position", "pressure", "surface"))
    peak = max(float(r[pressure]) for r in rows)
    check_true(f"{name}: in contact at t = 0.2 s ({len(rows)} Gauss points, largest pressure {peak:.4g} Pa)",
               len(rows) >= 4 and peak > 10.)
    for body in (1, 2):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(folder, f"body{body}_0001.vtu"))
        reader.Update()
        grid = reader.GetOutput()
        field = vtk_to_numpy(grid.GetPointData().GetArray("contact_pressure_Pa"))
        center = np.array([float(v) for v in values[f"Body {body}/Center"].split(",")])
        radius = float(values[f"Body {body}/Radius"])
        edges = arc_edges(grid, center, radius, lower=center[1] > 0.)
        worst, n = 0., 0
        for r in rows:
            if int(r[surface]) != body:
                continue
            # Half disks keep x >= centre x: the Gauss point is at x = |s|.
            value = field_at(edges, center[0] + abs(float(r[position])), field)
            if value is None:
                worst = float("inf")
                continue
            worst = max(worst, abs(value - float(r[pressure])))
            n += 1
        check_true(f"{name}, body {body}: {n} Gauss points found on the arc", n >= 2)
        check_close(f"{name}, body {body}: largest |VTU field - CSV pressure| [Pa] at the Gauss points",
                    worst, 0., 1e-10 * peak, relative=False)
report()
