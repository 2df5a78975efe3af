"""The ParaView output read back with VTK (Debian's python3-vtk9): point
and cell counts of each body's VTU against the cell counts and subdivisions
of summary.json, and the displacement at the probe points of summary.json."""
import json
import os
import sys
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy

from testing import check_close, check_true, report

out = sys.argv[1]  # the output directory of the Hertz test run
summary = json.load(open(os.path.join(out, "summary.json")))
s = summary["vtu_subdivisions"]

pvd = ET.parse(os.path.join(out, "solution.pvd")).getroot()
files = [d.attrib["file"] for d in pvd.iter("DataSet")]
check_true("solution.pvd lists %d time steps" % len(files), len(files) >= 2)
last = files[-1]
pvtu = vtk.vtkXMLPUnstructuredGridReader()
pvtu.SetFileName(os.path.join(out, last))
pvtu.Update()
number = last.split("_")[-1].split(".")[0]
total_points = 0
for b, n_cells in enumerate(summary["cells"]):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(out, f"body{b + 1}_{number}.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    # deal.II writes each cell as a patch of s x s cells with its own points.
    check_close(f"body{b + 1}: cells", grid.GetNumberOfCells(), n_cells * s * s, 0)
    check_close(f"body{b + 1}: points", grid.GetNumberOfPoints(), n_cells * (s + 1) ** 2, 0)
    total_points += grid.GetNumberOfPoints()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    u = vtk_to_numpy(grid.GetPointData().GetArray("displacement_m"))
    probe = summary["final_displacement_probe"][b]
    d2 = (points[:, 0] - probe["x_m"]) ** 2 + (points[:, 1] - probe["y_m"]) ** 2
    i = d2.argmin()
    check_true(f"body{b + 1}: a point at the probe", d2[i] < 1e-20)
    check_close(f"body{b + 1}: u_x at the probe [m]", u[i, 0], probe["ux_m"], 1e-6, relative=False)
    check_close(f"body{b + 1}: u_y at the probe [m]", u[i, 1], probe["uy_m"], 1e-6 * abs(probe["uy_m"]) + 1e-12,
                relative=False)
    for name in ["velocity_m_per_s", "von_mises_stress_Pa", "stress_xx_Pa"]:
        check_true(f"body{b + 1}: field {name}", grid.GetPointData().GetArray(name) is not None)
check_close("the .pvtu record joins both bodies (points)", pvtu.GetOutput().GetNumberOfPoints(), total_points, 0)
report()
