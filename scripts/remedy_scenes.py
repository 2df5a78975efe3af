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

usage: python3 scripts/remedy_scenes.py PROGRAM OUTPUT_DIR [DAMPING_RATIO | --sweep | --penalty-auto |
       --redistribution]"""
import csv
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
sys.path.insert(0, HERE)
from testing import edit_prm  # noqa: E402
from contact_measures import measures  # noqa: E402

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


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    program, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    sweep = "--sweep" in sys.argv
    penalty_auto = "--penalty-auto" in sys.argv
    redistribution = "--redistribution" in sys.argv
    xi = sys.argv[3] if len(sys.argv) > 3 and not (sweep or penalty_auto or redistribution) \
        else "0.2"
    ratios = ["0", "0.05", "0.1", "0.2", "0.3", "0.5"] if sweep else \
        ["0.1", "0.5", "1"] if penalty_auto else \
        ["plain", "redistribution"] if redistribution else ["0", xi]
    scenes = {"benchmark": {}} if (sweep or penalty_auto) else SCENES
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
                    else {"Contact/Damping ratio": "0", "Contact/Mass redistribution":
                          "true" if damping == "redistribution" else "false"} \
                    if redistribution else {"Contact/Damping ratio": damping}
                prm = edit_prm(os.path.join(ROOT, base), folder + ".prm", {
                    **edits, **setting,
                    "Time integration/Time step": "auto",
                    "Time integration/Allow time step above the stable estimate": "false",
                    "Output/Directory": folder, "Output/VTU interval": "0",
                    "Output/Pressure profile times": "0.375"})
                run = subprocess.run([program, prm], capture_output=True, text=True)
                row = {"scene": scene, "method": method, "damping_ratio": damping,
                       "exit_code": run.returncode}
                if run.returncode == 0:
                    row.update(measures(folder))
                rows.append(row)
                print(row, flush=True)
    keys = ["scene", "method", "damping_ratio", "exit_code", "time_step_s",
            "force_trend_peak_N_per_m", "force_chatter_percent",
            "pressure_trend_peak_Pa", "gauss_pressure_trend_peak_Pa",
            "profile_rms_percent_p0", "energy_error_percent",
            "damping_work_percent", "contact_duration_s", "wall_time_s"]
    with open(os.path.join(work, "remedy_sweep.csv" if sweep else "penalty_auto.csv"
                           if penalty_auto else "redistribution_scenes.csv"
                           if redistribution else "remedy_scenes.csv"),
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
