"""Higher-order VTU cells (Output/VTU cells = higher order) read back with
VTK (Debian's python3-vtk9): one cell per element, the geometry of the
curved boundary evaluated with VTK's own cells (vtkBezierQuadrilateral with
the RationalWeights, vtkLagrangeQuadrilateral), and the displacement at the
probe of summary.json.

- IGA (rational Bezier cells, degrees 2 and 3): every evaluated point of the
  arc lies at the radius to 1e-12 (relative): the rational Bezier form of a
  NURBS circle is exact.
- The same with `Output/VTU compression = true` (zlib blocks in the appended
  data instead of raw bytes).
- FEA (Lagrange cells of FE_Q(2) on MappingQ(2)): the quadratic through
  three points of an arc of angle theta is not the arc; its radial error is
  at most the interpolation bound R theta^3 sqrt(3)/216 (max |d^3x/ds^3| /
  3! times max |s (s - 1/2) (s - 1)| = sqrt(3)/36 on [0, 1]), asserted per
  edge; the measured error is printed.

usage: vtu_higher_order.py ISOIMPACT PRM_DIR WORK_DIR"""
import json
import math
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


def run(name, prm, edits):
    folder = os.path.join(work, name)
    path = edit_prm(os.path.join(prm_dir, prm), os.path.join(work, name + ".prm"),
                    {"Output/Directory": folder, "Output/VTU interval": "5",
                     "Output/VTU cells": "higher order", "Time integration/End time": "0.005",
                     "Output/Progress interval": "100", **edits})
    result = subprocess.run([program, path], capture_output=True, text=True)
    check_true(f"{name}: the run completes (exit {result.returncode})", result.returncode == 0)
    if result.returncode != 0:
        print(result.stdout[-2000:], result.stderr[-2000:])
        report()
    return folder, read_prm(path)


def read(folder, piece):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, piece))
    reader.Update()
    return reader.GetOutput()


def arc_errors(grid, center, radius):
    """Per edge of a cell whose two ends and middle lie on the circle: the
    edge's angle and the largest radial error at 41 points along it."""
    edges = []
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        weights = [0.] * cell.GetNumberOfPoints()
        for edge in EDGES:
            def at(t):
                x = [0., 0., 0.]
                cell.EvaluateLocation(vtk.mutable(0), edge(t), x, weights)
                return np.array(x[:2])
            ends = [at(0.), at(0.5), at(1.)]
            if max(abs(np.linalg.norm(x - center) - radius) for x in ends) > 1e-9 * radius:
                continue
            theta = 2. * math.asin(np.linalg.norm(ends[2] - ends[0]) / (2. * radius))
            error = max(abs(np.linalg.norm(at(t) - center) - radius) for t in np.linspace(0., 1., 41))
            edges.append((theta, error))
    return edges


for name, prm, edits, vtk_type in [
        ("iga_p2", "hertz_iga_hrz_coarse.prm", {}, vtk.VTK_BEZIER_QUADRILATERAL),
        ("iga_p2_zlib", "hertz_iga_hrz_coarse.prm", {"Output/VTU compression": "true"},
         vtk.VTK_BEZIER_QUADRILATERAL),
        ("iga_p3", "hertz_iga_hrz_coarse.prm", {"Discretization/Degree": "3"}, vtk.VTK_BEZIER_QUADRILATERAL),
        ("fea_q2", "hertz_fea_hrz_coarse.prm", {}, vtk.VTK_LAGRANGE_QUADRILATERAL)]:
    folder, prm_values = run(name, prm, edits)
    summary = json.load(open(os.path.join(folder, "summary.json")))
    check_true(f"{name}: summary.json says vtu_cells = higher order", summary["vtu_cells"] == "higher order")
    degree = int(prm_values["Discretization/Degree"])
    compressed = 'compressor="vtkZLibDataCompressor"' in open(os.path.join(folder, "body1_0000.vtu"),
                                                              errors="replace").read(400)
    check_true(f"{name}: zlib-compressed exactly when asked",
               compressed == (edits.get("Output/VTU compression") == "true"))
    center = np.array([float(v) for v in prm_values["Body 1/Center"].split(",")])
    radius = float(prm_values["Body 1/Radius"])

    # t = 0: the reference geometry.
    grid = read(folder, "body1_0000.vtu")
    n_cells = summary["cells"][0]
    check_close(f"{name}: one VTK cell per element", grid.GetNumberOfCells(), n_cells, 0)
    check_close(f"{name}: (p+1)^2 nodes per cell", grid.GetNumberOfPoints(), n_cells * (degree + 1) ** 2, 0)
    check_true(f"{name}: cell type {vtk_type}", all(grid.GetCellType(c) == vtk_type for c in range(n_cells)))
    degrees = vtk_to_numpy(grid.GetCellData().GetArray("HigherOrderDegrees"))
    check_true(f"{name}: HigherOrderDegrees = {degree}", np.all(degrees[:, :2] == degree))
    check_true(f"{name}: RationalWeights is the point data's rational-weights attribute",
               grid.GetPointData().GetRationalWeights() is not None)
    for field in ["displacement_m", "velocity_m_per_s", "stress_xx_Pa", "von_mises_stress_Pa"]:
        check_true(f"{name}: point field {field}", grid.GetPointData().GetArray(field) is not None)

    edges = arc_errors(grid, center, radius)
    check_true(f"{name}: {len(edges)} cell edges on the arc found", len(edges) >= 8)
    worst = max(error for _, error in edges)
    if vtk_type == vtk.VTK_BEZIER_QUADRILATERAL:
        check_close(f"{name}: largest radial error on the arc [m] (rational Bezier: exact)",
                    worst, 0., 1e-12 * radius, relative=False)
    else:
        ratio = max(error / (radius * theta ** 3 * math.sqrt(3.) / 216.) for theta, error in edges)
        print(f"     {name}: largest radial error on the arc {worst:.3e} m "
              f"(edge angle {edges[0][0]:.4f} rad; {100. * worst / radius:.2e} % of the radius)")
        check_true(f"{name}: radial error within R theta^3 sqrt(3)/216 on every arc edge "
                   f"(largest ratio {ratio:.3f})", ratio <= 1.)
        check_true(f"{name}: the quadratic Lagrange arc is not exact (error {worst:.2e} m > 1e-9 m)",
                   worst > 1e-9)

    # The last output: the displacement at the probe (a cell corner node).
    pvd = open(os.path.join(folder, "solution.pvd")).read()
    last = sorted(f for f in os.listdir(folder) if f.startswith("body1_") and f.endswith(".vtu"))[-1]
    check_true(f"{name}: solution.pvd lists {last[6:10]}", f"solution_{last[6:10]}.pvtu" in pvd)
    grid = read(folder, last)
    points = vtk_to_numpy(grid.GetPoints().GetData())
    u = vtk_to_numpy(grid.GetPointData().GetArray("displacement_m"))
    probe = summary["final_displacement_probe"][0]
    d2 = (points[:, 0] - probe["x_m"]) ** 2 + (points[:, 1] - probe["y_m"]) ** 2
    i = d2.argmin()
    check_true(f"{name}: a node at the probe", d2[i] < 1e-20)
    check_close(f"{name}: u_y at the probe [m]", u[i, 1], probe["uy_m"], 1e-10 * abs(probe["uy_m"]), relative=False)

    # The .pvtu record joins both bodies.
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, f"solution_{last[6:10]}.pvtu"))
    reader.Update()
    check_close(f"{name}: the .pvtu joins both bodies (cells)", reader.GetOutput().GetNumberOfCells(),
                sum(summary["cells"]), 0)
report()
