#!/usr/bin/env python3
"""Checks a chatter remedy beyond the benchmark (doc/results.md): the
benchmark files prm/hertz_fea_hrz.prm, hertz_fea_q8_hrz.prm and
prm/hertz_iga_hrz.prm, level 4,
on other scenes, each without and with the remedy (Contact/Damping ratio),
at the automatic stable step. Prints a markdown table of the measures of
scripts/contact_measures.py and writes OUTPUT_DIR/remedy_scenes.csv.

With --sweep instead: the benchmark scene only, for the damping ratios
0, 0.05, 0.1, 0.2, 0.3, 0.5. With --penalty-auto: the benchmark scene,
undamped, with Contact/Penalty = auto at scale factors 0.1, 0.5, 1 (the
damping_ratio column then holds the scale factor). With --redistribution:
the scenes without and with Contact/Mass redistribution (undamped; the
damping_ratio column then holds "plain" or "redistribution").

With --bipenalty: the benchmark scene only, undamped, without and with
Contact/Bipenalty, momentum and velocity switching (the damping_ratio
column holds "plain", "bipenalty" or "bipenalty_velocity"),
both at the benchmark files' step 5e-4 s (the same step, so that the time
loop's cost per step compares; benchmarks/bipenalty.sh); writes
OUTPUT_DIR/bipenalty.csv with the cost per step and the bipenalty's energy
terms (largest kinetic energy of the mass penalty and largest energy its
switching brought in, in % of the input energy). With --bipenalty --auto
the same at the automatic step of each run (OUTPUT_DIR/bipenalty.csv too:
use another OUTPUT_DIR).

With --redistribution: every scene without and with Contact/Mass
redistribution at the automatic step (OUTPUT_DIR/redistribution_scenes.csv).

usage: python3 scripts/remedy_scenes.py PROGRAM OUTPUT_DIR [DAMPING_RATIO | --sweep | --penalty-auto |
       --bipenalty [--auto] | --redistribution]"""
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
sys.path.insert(0, HERE)
from testing import edit_prm  # noqa: E402
from contact_measures import measures  # noqa: E402
from isoimpact_results import read_history  # noqa: E402

SCENES = {
    "benchmark": {},
    "unequal cylinders (R1 = 2 m, E1 = 5000 Pa)": {
        "Body 1/Radius": "2", "Body 1/Center": "0, 2",
        "Body 1/Material/Young's modulus": "5000"},
    "rigid plane (eps 2e5 Pa/m)": {
        "Obstacle/Type": "plane", "Obstacle/Point": "0, 0",
        "Obstacle/Normal": "0, 1", "Obstacle/Penalty": "2e5"},
    "fast impact (5 m/s each)": {
        "Body 1/Initial velocity": "0, -5", "Body 2/Initial velocity": "0, 5"},
    "slow impact (0.2 m/s each)": {
        "Body 1/Initial velocity": "0, -0.2", "Body 2/Initial velocity": "0, 0.2",
        "Time integration/End time": "1.6"},
    "stiff penalty (1e6 Pa/m)": {"Contact/Penalty": "1e6"},
    "soft penalty (1e4 Pa/m)": {"Contact/Penalty": "1e4"},
}
FILES = {"FEA Q9 HRZ": "prm/hertz_fea_hrz.prm", "FEA Q8 HRZ": "prm/hertz_fea_q8_hrz.prm",
         "IGA p2 HRZ": "prm/hertz_iga_hrz.prm"}


def bipenalty_measures(folder):
    """Cost per step of the time loop (summary.json) and the bipenalty's
    energy terms in % of the input energy (history.csv)."""
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    loop = float(summary["wall_time_parts_s"]["time_loop"])
    row = {"stable_time_step_bound_s": summary["stable_time_step_bound_s"],
           "time_loop_s": loop, "steps": summary["steps"],
           "cost_per_step_ms": 1e3 * loop / summary["steps"]}
    history = read_history(folder)
    e0 = history["total_energy"][0]
    for column, key in [("bipenalty_kinetic_energy_J_per_m", "bipenalty_kinetic_max_percent"),
                        ("bipenalty_switching_work_J_per_m",
                         "bipenalty_switching_max_percent")]:
        if column in history:
            row[key] = 100 * float(max(abs(history[column]))) / e0
    return row


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    program, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    sweep = "--sweep" in sys.argv
    penalty_auto = "--penalty-auto" in sys.argv
    bipenalty = "--bipenalty" in sys.argv
    redistribution = "--redistribution" in sys.argv
    xi = sys.argv[3] if len(sys.argv) > 3 and not (sweep or penalty_auto or bipenalty or redistribution) \
        else "0.2"
    ratios = ["0", "0.05", "0.1", "0.2", "0.3", "0.5"] if sweep else \
        ["0.1", "0.5", "1"] if penalty_auto else \
        ["plain", "bipenalty", "bipenalty_velocity"] if bipenalty else \
        ["plain", "redistribution"] if redistribution else ["0", xi]
    scenes = {"benchmark": {}} if (sweep or penalty_auto or bipenalty) else SCENES
    os.makedirs(work, exist_ok=True)
    rows = []
    for scene, edits in scenes.items():
        for method, base in FILES.items():
            for damping in ratios:
                name = "".join(c if c.isalnum() else "_" for c in
                               f"{scene[:20]}_{method}_{damping}")
                folder = os.path.join(work, name)
                setting = {"Contact/Penalty": "auto", "Contact/Damping ratio": "0",
                           "Contact/Penalty scale factor": damping} if penalty_auto \
                    else {"Contact/Damping ratio": "0",
                          "Contact/Bipenalty": str(damping != "plain").lower(),
                          "Contact/Bipenalty switching":
                          "velocity" if damping == "bipenalty_velocity" else "momentum"} \
                    if bipenalty else {"Contact/Damping ratio": "0", "Contact/Mass redistribution":
                                       "true" if damping == "redistribution" else "false"} \
                    if redistribution else {"Contact/Damping ratio": damping}
                step = {"Time integration/Time step": "5e-4",
                        "Time integration/Allow time step above the stable estimate":
                        "true"} if bipenalty and "--auto" not in sys.argv else {
                    "Time integration/Time step": "auto",
                    "Time integration/Allow time step above the stable estimate": "false"}
                prm = edit_prm(os.path.join(ROOT, base), folder + ".prm", {
                    **edits, **setting, **step,
                    "Output/Directory": folder, "Output/VTU interval": "0",
                    "Output/History interval": "1",
                    "Output/Pressure profile times": "0.375"})
                run = subprocess.run([program, prm], capture_output=True, text=True)
                row = {"scene": scene, "method": method, "damping_ratio": damping,
                       "exit_code": run.returncode}
                if run.returncode == 0:
                    row.update(measures(folder))
                    if bipenalty:
                        row.update(bipenalty_measures(folder))
                rows.append(row)
                print(row, flush=True)
    keys = ["scene", "method", "damping_ratio", "exit_code", "time_step_s",
            "force_trend_peak_N_per_m", "force_chatter_percent",
            "pressure_trend_peak_Pa", "gauss_pressure_trend_peak_Pa",
            "profile_rms_percent_p0", "energy_error_percent",
            "damping_work_percent", "contact_duration_s", "wall_time_s"]
    if bipenalty:
        keys += ["stable_time_step_bound_s", "time_loop_s", "steps",
                 "cost_per_step_ms", "bipenalty_kinetic_max_percent",
                 "bipenalty_switching_max_percent"]
    with open(os.path.join(work, "remedy_sweep.csv" if sweep else "penalty_auto.csv"
                           if penalty_auto else "bipenalty.csv" if bipenalty
                           else "redistribution_scenes.csv" if redistribution
                           else "remedy_scenes.csv"),
              "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    print("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys))
    for r in rows:
        print("| " + " | ".join(f"{r.get(k):.4g}" if isinstance(r.get(k), float)
                                else str(r.get(k, "")) for k in keys) + " |")


if __name__ == "__main__":
    main()
