"""Bad parameter files: unknown key, wrong type, out-of-range value, missing
file. Each must give a non-zero exit, a message naming the parameter (and
the file), and no output directory."""
import os
import shutil
import subprocess
import sys

from testing import check_true, edit_prm, report

program, good_prm, workdir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(workdir, exist_ok=True)
base = {"Output/Directory": "bad_output"}

cases = {
    "unknown_key": ({"Contact/Penalty per pass": None, "Contact/Penalty per passage": "half"},
                    ["Penalty per passage"]),
    "wrong_type": ({"Time integration/Time step": "fast"}, ["Time step", "fast"]),
    "out_of_range": ({"Body 1/Material/Poisson's ratio": "0.7"}, ["Poisson's ratio", "0.7"]),
    "negative_modulus": ({"Body 1/Material/Young's modulus": "-5"}, ["Young's modulus", "-5"]),
    "unknown_scheme": ({"Mass matrix/Scheme": "diagonal"}, ["Scheme", "diagonal"]),
}
# The rigid obstacle (subsection Obstacle): a zero normal, a non-positive
# radius or penalty.
cases.update({
    "obstacle_zero_normal": ({"Obstacle/Type": "plane", "Obstacle/Normal": "0, 0"},
                             ["Obstacle/Normal", "(0, 0)", "non-zero"]),
    "obstacle_zero_radius": ({"Obstacle/Type": "cylinder", "Obstacle/Radius": "0"},
                             ["Obstacle/Radius", "value 0", "positive"]),
    "obstacle_negative_penalty": ({"Obstacle/Type": "plane", "Obstacle/Penalty": "-2e5"},
                                  ["Obstacle/Penalty", "-200000", "positive"]),
    "obstacle_unknown_type": ({"Obstacle/Type": "sphere", "Obstacle/Penalty": "2e5"},
                              ["Type", "sphere"]),
})
# The element and discretisation choices the patterns cannot refuse.
q8 = {"Discretization/FEA element": "serendipity"}
cases.update({
    "q8_row_sum": ({**q8, "Mass matrix/Scheme": "row-sum"},
                   ["Mass matrix/Scheme", "row-sum", "negative corner masses"]),
    "q8_with_iga": ({**q8, "Discretization/Method": "iga"},
                    ["Discretization/FEA element", "serendipity", "Method = fea"]),
})
for name, (edits, words) in cases.items():
    prm = edit_prm(good_prm, os.path.join(workdir, name + ".prm"), {**base, **edits})
    shutil.rmtree(os.path.join(workdir, "bad_output"), ignore_errors=True)
    run = subprocess.run([program, prm], cwd=workdir, capture_output=True, text=True)
    message = run.stderr
    print(f"--- {name}: exit {run.returncode}\n{message.strip()}")
    check_true(f"{name}: non-zero exit", run.returncode != 0)
    check_true(f"{name}: message names the file", prm in message)
    for word in words:
        check_true(f"{name}: message names '{word}'", word in message)
    check_true(f"{name}: no output directory", not os.path.exists(os.path.join(workdir, "bad_output")))

missing = os.path.join(workdir, "does_not_exist.prm")
run = subprocess.run([program, missing], cwd=workdir, capture_output=True, text=True)
check_true("missing file: non-zero exit", run.returncode != 0)
check_true("missing file: message names the file", missing in run.stderr)

# --print-parameters writes a complete file that the program reads back.
run = subprocess.run([program, "--print-parameters"], capture_output=True, text=True)
check_true("--print-parameters exits with 0", run.returncode == 0)
defaults = os.path.join(workdir, "defaults.prm")
with open(defaults, "w") as f:
    f.write(run.stdout)
for key in ["Body 1", "Body 2", "Mass matrix", "Contact", "Obstacle", "Time integration", "Output",
            "Young's modulus", "Penalty per pass"]:
    check_true(f"--print-parameters documents '{key}'", key in run.stdout)
run = subprocess.run([program, "--help"], capture_output=True, text=True)
check_true("--help exits with 0 and shows usage", run.returncode == 0 and "usage" in run.stdout)
report()
