"""Scene reduction: the dynamic Hertz impact of two half cylinders
(tests/prm/hertz_fea_hrz_coarse.prm) against one half cylinder hitting the
rigid plane y = 0 (tests/prm/hertz_fea_hrz_rigid_plane_coarse.prm, obstacle
penalty 2 eps_N), same mesh (256 cells per half cylinder), HRZ mass and time
step (5e-4 s).

Why the raw histories are not compared pointwise within 1 % over the whole
impact: the raw penalty force of this benchmark chatters at the period of a
few steps (doc/formulation.md), and that chatter is sensitive to any
perturbation. Measured: the two-body run with its penalty changed by 1e-6
(relative) differs from itself by up to 64 % of the peak force pointwise
(raw), 8.4 % after the 10-ms filter and 2.1 % after a 50-ms filter; its raw
peak moves by 6.5 %. The reduction is not bit-identical to the two-body
model (the two-pass contact measures the gap along the other surface's
discrete normal and puts half of the force at the projection points, the
plane at the Gauss points along the exact normal): the early force agrees to
0.02 % (t <= 0.02 s) and 0.6 % (t <= 0.05 s), after which the difference is
amplified like any perturbation: 73 % raw, 8.5 % (10 ms), 2.3 % (50 ms).
Ensembles of 6 two-body and 5 reduction runs (penalties perturbed by 1e-6
to 1e-4) have the same spreads; the means of their 50-ms-filtered peaks
differ by 0.3 %.

Asserted (measured values in brackets):
- early phase, t <= 0.05 s: max |F_plane - F_two| / max F_two <= 1 % (0.61 %);
- 50-ms-filtered peak force within 1 % (-0.82 %);
- impulse (integral of the force over time) within 0.1 % (1e-5);
- contact duration within 1 % (0);
- over the whole history, raw and filtered (10 ms, 50 ms): the reduction's
  deviation from the two-body run is at most 1.5 times the two-body run's
  own deviation under a 1e-6 change of its penalty (ratios 1.14, 1.01, 1.10);
- contact energy of the one body = half the two-body one (penalty
  equivalence), early phase within 1 % of its peak; initial energy of one full
  cylinder; energy error below 2 %; one body in summary.json and the VTU;
- a rigid cylinder (radius 4, centre (0, -4), body outside) in place of the
  plane: energy error below 2 %, filtered peak force and duration within
  10 % of the quasi-static Hertz impact against a rigid cylinder (the
  tolerance of the two-body benchmark; measured +0.6 % and -2.5 %), and
  peak and duration ordered against the plane's as the analytic ones are
  (the more curved partner, R* = R/2 instead of R, gives a smaller contact
  width, hence in 2D a larger approach for the same force: a softer
  contact, a lower peak (417.5 against 471.5 N/m) and a longer impact).
- the same reduction with NURBS (tests/prm/hertz_iga_consistent_coarse.prm,
  the same code path): early force (t <= 0.05 s) within 1 % (0.12 %),
  impulse within 0.1 % (1.6e-4); not asserted: 50-ms-filtered peak -1.75 %.
Printed, not asserted: wall times, steps and unknowns."""
import json
import os
import shutil
import subprocess
import sys

from testing import check_close, check_true, edit_prm, read_prm, report

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "scripts"))
from isoimpact_results import moving_average, read_history, window_width  # noqa: E402

program, prm_two, prm_plane, prm_iga_two, workdir = sys.argv[1:6]
os.makedirs(workdir, exist_ok=True)


def run(prm, name):
    out = os.path.join(workdir, name)
    shutil.rmtree(out, ignore_errors=True)
    result = subprocess.run([program, prm], cwd=workdir, capture_output=True, text=True)
    print(result.stdout[-600:], result.stderr[-1500:])
    check_true(f"{name}: program exits with 0", result.returncode == 0)
    return out


def variant(prm, name, edits):
    """A copy of prm with the edits and its output directory named name."""
    edits = {**edits, "Output/Directory": name}
    path = edit_prm(prm, os.path.join(workdir, name + ".prm"), edits)
    values = read_prm(path)
    check_true(f"{name}: {edits} set in {os.path.basename(path)}",
               all(values.get(key) == str(value) for key, value in edits.items()))
    return path


def filtered(f, dt, window):
    return moving_average(f, window_width(window, dt))


def deviation(a, b, scale):
    return max(abs(x - y) for x, y in zip(a, b)) / scale


two_dir = run(prm_two, "hertz_fea_hrz_coarse")
perturbed_dir = run(variant(prm_two, "two_bodies_perturbed", {"Contact/Penalty": "1.000001e5"}),
                    "two_bodies_perturbed")
plane_dir = run(prm_plane, "hertz_fea_hrz_rigid_plane_coarse")
two, perturbed, plane = read_history(two_dir), read_history(perturbed_dir), read_history(plane_dir)
s_two = json.load(open(os.path.join(two_dir, "summary.json")))
s_plane = json.load(open(os.path.join(plane_dir, "summary.json")))

time = two["time"]
dt = time[1] - time[0]
check_true("same number of history rows (%d, %d)" % (len(time), len(plane["time"])),
           len(time) == len(plane["time"]))
check_true("same times", max(abs(a - b) for a, b in zip(time, plane["time"])) < 1e-9)
f_two, f_pert, f_plane = two["contact_force"], perturbed["contact_force"], plane["contact_force"]
peak_two = max(f_two)
early = [i for i, t in enumerate(time) if t <= 0.05 + 1e-12]
check_close("early phase (t <= 0.05 s): max |F_plane - F_two| / max F_two",
            deviation([f_plane[i] for i in early], [f_two[i] for i in early], peak_two), 0., 0.01,
            relative=False)
print("raw peaks: two bodies %.2f, perturbed %.2f, plane %.2f N/m (not asserted: chatter)"
      % (peak_two, max(f_pert), max(f_plane)))
for window in [0., 0.01, 0.05]:
    a = filtered(f_two, dt, window) if window else f_two
    b = filtered(f_pert, dt, window) if window else f_pert
    c = filtered(f_plane, dt, window) if window else f_plane
    own, reduction = deviation(b, a, max(a)), deviation(c, a, max(a))
    what = "raw" if window == 0. else "filtered %g ms" % (1e3 * window)
    print(f"{what}: max deviation from the two-body run: two bodies with eps_N (1 + 1e-6) "
          f"{own:.4f}, rigid plane {reduction:.4f} (ratio {reduction / own:.3f})")
    check_true(f"{what}: reduction's deviation {reduction:.4f} <= 1.5 x the two-body run's own "
               f"sensitivity {own:.4f}", reduction <= 1.5 * own)
    if window == 0.05:
        check_close("50-ms-filtered peak force [N/m], plane vs two bodies", max(c), max(a), 0.01)


def impulse(f):
    return sum(0.5 * (f[i] + f[i + 1]) * (time[i + 1] - time[i]) for i in range(len(f) - 1))


check_close("impulse [N s/m], plane vs two bodies", impulse(f_plane), impulse(f_two), 1e-3)
check_close("contact duration [s], plane vs two bodies", s_plane["contact_duration_s"],
            s_two["contact_duration_s"], 0.01)
e_two = max(two["contact_energy"])
check_close("early phase: max |E_c,plane - E_c,two / 2| / (max E_c,two / 2)",
            deviation([plane["contact_energy"][i] for i in early],
                      [0.5 * two["contact_energy"][i] for i in early], 0.5 * e_two),
            0., 0.01, relative=False)
check_close("initial total energy [J/m] = 1/2 rho pi R^2 v^2 (one full cylinder)",
            plane["total_energy"][0], 0.5 * 3.141592653589793 * 16 * 4, 2e-3)
check_true("max energy error %.3g below 2 %%" % s_plane["max_energy_error"],
           s_plane["max_energy_error"] < 0.02)
check_true("summary names the obstacle", s_plane["obstacle"] == "plane")
check_true("one body in the summary", len(s_plane["cells"]) == 1
           and len(s_plane["final_displacement_probe"]) == 1)
check_true("solution.pvd written", os.path.exists(os.path.join(plane_dir, "solution.pvd")))

print(f"cost: two bodies {s_two['unknowns']} unknowns, {s_two['steps']} steps, "
      f"{s_two['wall_time_s']:.2f} s; rigid plane {s_plane['unknowns']} unknowns, "
      f"{s_plane['steps']} steps, {s_plane['wall_time_s']:.2f} s (ratio "
      f"{s_plane['wall_time_s'] / s_two['wall_time_s']:.2f}; wall times on a shared machine)")

# The same reduction with NURBS: the obstacle sees IGA boundary spans
# through the same segments.
# (variant() without edits: only the output directory is renamed.)
iga_two_dir = run(variant(prm_iga_two, "iga_two_bodies", {}), "iga_two_bodies")
iga_plane_prm = variant(prm_iga_two, "iga_rigid_plane",
                        {"Obstacle/Type": "plane", "Obstacle/Penalty": "2e5"})
iga_plane_dir = run(iga_plane_prm, "iga_rigid_plane")
h_two, h_plane = read_history(iga_two_dir), read_history(iga_plane_dir)
time = h_two["time"]
f_two, f_plane = h_two["contact_force"], h_plane["contact_force"]
early = [i for i, t in enumerate(time) if t <= 0.05 + 1e-12]
check_close("IGA: early phase (t <= 0.05 s): max |F_plane - F_two| / max F_two",
            deviation([f_plane[i] for i in early], [f_two[i] for i in early], max(f_two)), 0., 0.01,
            relative=False)
check_close("IGA: impulse [N s/m], plane vs two bodies", impulse(f_plane), impulse(f_two), 1e-3)
dt = time[1] - time[0]
print("IGA: 50-ms-filtered peaks: two bodies %.2f, plane %.2f N/m" % (
    max(filtered(f_two, dt, 0.05)), max(filtered(f_plane, dt, 0.05))))

# The same body against a rigid cylinder of its own radius.
prm_cylinder = variant(prm_plane, "hertz_fea_hrz_rigid_cylinder_coarse",
                       {"Obstacle/Type": "cylinder", "Obstacle/Center": "0, -4",
                        "Obstacle/Radius": "4"})
cylinder_dir = run(prm_cylinder, "hertz_fea_hrz_rigid_cylinder_coarse")
s_cyl = json.load(open(os.path.join(cylinder_dir, "summary.json")))
print("rigid cylinder: filtered peak %.2f N/m (analytic %.2f), duration %.4f s (analytic %.4f)" % (
    s_cyl["filtered_peak_contact_force_N_per_m"], s_cyl["analytic"]["peak_contact_force_N_per_m"],
    s_cyl["contact_duration_s"], s_cyl["analytic"]["contact_duration_s"]))
check_true("rigid cylinder: max energy error %.3g below 2 %%" % s_cyl["max_energy_error"],
           s_cyl["max_energy_error"] < 0.02)
check_close("rigid cylinder: filtered peak force [N/m] vs rigid-limit Hertz",
            s_cyl["filtered_peak_contact_force_N_per_m"],
            s_cyl["analytic"]["peak_contact_force_N_per_m"], 0.10)
check_close("rigid cylinder: contact duration [s] vs rigid-limit Hertz",
            s_cyl["contact_duration_s"], s_cyl["analytic"]["contact_duration_s"], 0.10)
analytic_plane = s_plane["analytic"]
check_true("rigid cylinder: analytic peak below the plane's (%.2f < %.2f N/m), duration longer"
           % (s_cyl["analytic"]["peak_contact_force_N_per_m"],
              analytic_plane["peak_contact_force_N_per_m"]),
           s_cyl["analytic"]["peak_contact_force_N_per_m"] < analytic_plane["peak_contact_force_N_per_m"]
           and s_cyl["analytic"]["contact_duration_s"] > analytic_plane["contact_duration_s"])
check_true("rigid cylinder: computed filtered peak below the plane's (%.2f < %.2f N/m), "
           "duration longer (%.4f > %.4f s)"
           % (s_cyl["filtered_peak_contact_force_N_per_m"],
              s_plane["filtered_peak_contact_force_N_per_m"], s_cyl["contact_duration_s"],
              s_plane["contact_duration_s"]),
           s_cyl["filtered_peak_contact_force_N_per_m"] < s_plane["filtered_peak_contact_force_N_per_m"]
           and s_cyl["contact_duration_s"] > s_plane["contact_duration_s"])
report()
