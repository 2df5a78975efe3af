#!/usr/bin/env python3
"""Is the analytic Hertz reference or the model off for unequal cylinders?
(doc/results.md). The reference is quasi-static; it holds when the contact
lasts long against the bodies' slowest vibrations. A slower impact lasts
longer (duration ~ v^-1/5), so the model's filtered peak force and contact
duration must approach the reference as the closing speed falls.
Runs prm/hertz_fea_hrz.prm (level 4, contact damping xi = 0.2, automatic
step; local refinement at the slow speeds) for the equal cylinders of the benchmark and the unequal ones of
scripts/remedy_scenes.py (R1 = 2 m, E1 = 5000 Pa) at speeds 2, 1, 0.1 and
0.01 m/s each, and prints model / reference for the filtered peak force
(summary.json, 10 ms window) and the contact duration.

usage: python3 scripts/quasi_static_limit.py PROGRAM OUTPUT_DIR"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
from testing import edit_prm  # noqa: E402

SCENES = {"equal (R = 4 m, E = 1000 Pa)": {},
          "unequal (R1 = 2 m, E1 = 5000 Pa)": {
              "Body 1/Radius": "2", "Body 1/Center": "0, 2",
              "Body 1/Material/Young's modulus": "5000"}}
SPEEDS = ["2", "1", "0.1", "0.01"]
# The contact zone shrinks with the speed (a ~ sqrt(P)): local refinement
# around the first contact keeps at least 6 faces across it.
LOCAL_REFINEMENT = {"0.1": ("2", "1.2"), "0.01": ("3", "0.6")}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    program, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(work, exist_ok=True)
    print("| scene | speed each [m/s] | filtered peak [N/m] | reference [N/m] | ratio | "
          "duration [s] | reference [s] | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, edits in SCENES.items():
        for speed in SPEEDS:
            name = f"{'unequal' if edits else 'equal'}_v{speed}"
            directory = os.path.join(work, name)
            edits_run = dict(edits)
            edits_run.update({
                "Time integration/Time step": "auto",
                "Time integration/Allow time step above the stable estimate": "false",
                "Time integration/End time": "2.0" if float(speed) < 0.5 else "1.0",
                "Contact/Damping ratio": "0.2",
                "Body 1/Initial velocity": f"0, -{speed}",
                "Body 2/Initial velocity": f"0, {speed}",
                "Output/Directory": directory, "Output/VTU interval": "0",
                "Output/Progress interval": "100"})
            if speed in LOCAL_REFINEMENT:
                levels, radius = LOCAL_REFINEMENT[speed]
                edits_run.update({"Discretization/Local refinements": levels,
                                  "Discretization/Refinement radius": radius})
            prm = edit_prm(os.path.join(ROOT, "prm", "hertz_fea_hrz.prm"),
                           os.path.join(work, name + ".prm"), edits_run)
            subprocess.check_call([program, prm], stdout=subprocess.DEVNULL)
            with open(os.path.join(directory, "summary.json")) as f:
                s = json.load(f)
            peak, duration = s["filtered_peak_contact_force_N_per_m"], s["contact_duration_s"]
            a = s["analytic"]
            print(f"| {scene} | {speed} | {peak:.4g} | {a['peak_contact_force_N_per_m']:.4g} | "
                  f"{peak / a['peak_contact_force_N_per_m']:.3f} | {duration:.3f} | "
                  f"{a['contact_duration_s']:.3f} | {duration / a['contact_duration_s']:.3f} |",
                  flush=True)


if __name__ == "__main__":
    main()
