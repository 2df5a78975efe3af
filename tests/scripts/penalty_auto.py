"""Contact/Penalty = auto (k = s mu / dt^2, s = 0.5 by default; scene.cc,
doc/formulation.md) on the coarse benchmark meshes (level 3), undamped, at
the automatic step:

- the rigid-plane reduction gets exactly twice the two-body penalty (the
  same mu / dt^2 with the unreduced surface mass; the equivalent obstacle
  penalty of a symmetric impact is 2 eps_N), 1e-9;
- FEA Q9 HRZ and IGA p2 HRZ complete with the force trend peak within 1.5 %
  of the converged 430.7 N/m, force chatter below 5 %, consistent pressure
  trend peak within 10 % of p0 = 197.7 Pa, energy balance within 0.1 %.
Measured: penalties 7991 (FEA) and 3076 Pa/m (IGA); trend peaks 430.5 and
426.7 N/m; chatter 3.1 and 3.0 %; pressure 206.1 and 185.9 Pa.

usage: penalty_auto.py PROGRAM TESTS_PRM_DIR WORKDIR"""
import os
import re
import shutil
import subprocess
import sys

from testing import check_close, check_true, edit_prm, report

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "scripts"))
from contact_measures import measures  # noqa: E402

program, prm_dir, workdir = sys.argv[1:4]
os.makedirs(workdir, exist_ok=True)


def run(base):
    folder = os.path.join(workdir, base[:-4])
    shutil.rmtree(folder, ignore_errors=True)
    prm = edit_prm(os.path.join(prm_dir, base), folder + ".prm", {
        "Contact/Penalty": "auto",
        "Time integration/Time step": "auto",
        "Time integration/Allow time step above the stable estimate": "false",
        "Output/Directory": folder, "Output/VTU interval": "0",
        "Output/History interval": "1", "Output/Pressure profile times": "0.375"})
    result = subprocess.run([program, prm], capture_output=True, text=True)
    check_true(f"{base}: exit 0", result.returncode == 0)
    penalty = float(re.search(r"penalty ([0-9.e+-]+) Pa/m", result.stdout).group(1))
    m = measures(folder)
    print(base, f"penalty {penalty} Pa/m", {k: round(v, 5) if isinstance(v, float) else v
                                             for k, v in m.items()})
    return penalty, m


fea_penalty, fea = run("hertz_fea_hrz_coarse.prm")
iga_penalty, iga = run("hertz_iga_hrz_coarse.prm")
rigid_penalty, _ = run("hertz_fea_hrz_rigid_plane_coarse.prm")
check_close("rigid-plane auto penalty = 2 x two-body auto penalty",
            rigid_penalty, 2 * fea_penalty, 1e-5)  # printed with 6 digits
for name, m in [("FEA Q9 HRZ", fea), ("IGA p2 HRZ", iga)]:
    check_close(f"{name}: force trend peak [N/m]", m["force_trend_peak_N_per_m"], 430.7, 0.015)
    check_true(f"{name}: chatter {m['force_chatter_percent']:.2f} % < 5 %",
               m["force_chatter_percent"] < 5)
    check_close(f"{name}: consistent pressure trend peak [Pa]",
                m["pressure_trend_peak_Pa"], 197.7, 0.10)
    check_true(f"{name}: energy balance {m['energy_error_percent']:.4f} % < 0.1 %",
               m["energy_error_percent"] < 0.1)
report()
