"""Refinement study in CI: FEA (FE_Q(2)) and IGA (quadratic NURBS, four
patches) with HRZ mass on the same coarse mesh, refined 2, 3 and 4 times
(64, 256, 1024 elements per half cylinder). Checks (issue: on the finest
level that fits in CI, FEA and IGA peak forces within 2 % of each other):
- level 4: the filtered peak contact forces of FEA and IGA within 2 % of
  each other, their contact durations within 3 %;
- FEA and IGA approach each other: the peak-force gap at level 4 is smaller
  than at level 2;
- every run: energy error below 2 %.
Peaks are those of the force filtered over 10 ms (summary.json), since the
raw penalty force chatters (doc/oscillation.md)."""
import json
import os
import shutil
import subprocess
import sys

from testing import check_close, check_true, edit_prm, report

program, source_dir, workdir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(workdir, exist_ok=True)


def prm_file(method, level):
    if level == 4:
        return os.path.join(source_dir, "prm", f"hertz_{method}_hrz.prm")
    return os.path.join(source_dir, "prm", "refinement", f"hertz_{method}_hrz_g{level}.prm")


def run(method, level):
    name = f"{method}_level{level}"
    prm = edit_prm(prm_file(method, level), os.path.join(workdir, name + ".prm"),
                   {"Output/Directory": name, "Output/VTU interval": 0})
    shutil.rmtree(os.path.join(workdir, name), ignore_errors=True)
    result = subprocess.run([program, prm], cwd=workdir, capture_output=True, text=True)
    check_true(f"{name}: program exits with 0", result.returncode == 0)
    summary = json.load(open(os.path.join(workdir, name, "summary.json")))
    print(f"  {name}: {summary['unknowns']} unknowns, filtered peak "
          f"{summary['filtered_peak_contact_force_N_per_m']:.1f} N/m, duration "
          f"{summary['contact_duration_s']:.4f} s, energy error "
          f"{100 * summary['max_energy_error']:.3f} %")
    check_true(f"{name}: energy error {summary['max_energy_error']:.3g} below 2 %",
               summary["max_energy_error"] < 0.02)
    return summary


results = {(m, l): run(m, l) for l in (2, 3, 4) for m in ("fea", "iga")}
peak = {k: s["filtered_peak_contact_force_N_per_m"] for k, s in results.items()}
gap = {l: abs(peak[("fea", l)] - peak[("iga", l)]) / peak[("fea", l)] for l in (2, 3, 4)}
print("  FEA-IGA peak-force gap by level: " +
      ", ".join(f"level {l}: {100 * g:.2f} %" for l, g in gap.items()))
check_close("level 4: IGA filtered peak force [N/m] against FEA's",
            peak[("iga", 4)], peak[("fea", 4)], 0.02)
check_close("level 4: IGA contact duration [s] against FEA's",
            results[("iga", 4)]["contact_duration_s"],
            results[("fea", 4)]["contact_duration_s"], 0.03)
check_true(f"the gap shrinks under refinement: {100 * gap[4]:.2f} % (level 4) < "
           f"{100 * gap[2]:.2f} % (level 2)", gap[4] < gap[2])
report()
