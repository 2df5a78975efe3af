"""Bad parameter files: unknown key, wrong type, out-of-range value, missing
file. Each must give a non-zero exit, a message naming the parameter (and
the file), and no output directory."""
import os
import shutil
import subprocess
import sys

from testing import check_true, report

program, good_prm, workdir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(workdir, exist_ok=True)
base = open(good_prm).read().replace("hertz_fea_hrz_coarse", "bad_output")

cases = {
    "unknown_key": (base.replace("set Penalty per pass", "set Penalty per passage"),
                    ["Penalty per passage"]),
    "wrong_type": (base.replace("set Time step = 5e-4", "set Time step = fast"),
                   ["Time step", "fast"]),
    "out_of_range": (base.replace("set Poisson's ratio = 0.2", "set Poisson's ratio = 0.7", 1),
                     ["Poisson's ratio", "0.7"]),
    "negative_modulus": (base.replace("set Young's modulus = 1000", "set Young's modulus = -5", 1),
                         ["Young's modulus", "-5"]),
    "unknown_scheme": (base.replace("set Scheme = HRZ", "set Scheme = diagonal"),
                       ["Scheme", "diagonal"]),
}
# The rigid obstacle (subsection Obstacle): a zero normal, a non-positive
# radius or penalty.
obstacle = "\nsubsection Obstacle\n  set Type = %s\n  set %s = %s\nend\n"
cases.update({
    "obstacle_zero_normal": (base + obstacle % ("plane", "Normal", "0, 0"),
                             ["Obstacle/Normal", "(0, 0)", "non-zero"]),
    "obstacle_zero_radius": (base + obstacle % ("cylinder", "Radius", "0"),
                             ["Obstacle/Radius", "value 0", "positive"]),
    "obstacle_negative_penalty": (base + obstacle % ("plane", "Penalty", "-2e5"),
                                  ["Obstacle/Penalty", "-200000", "positive"]),
    "obstacle_unknown_type": (base + obstacle % ("sphere", "Penalty", "2e5"),
                              ["Type", "sphere"]),
})
# The element and discretisation choices the patterns cannot refuse.
q8 = base.replace("set Method             = fea",
                  "set Method             = fea\n  set FEA element        = serendipity")
cases.update({
    "q8_row_sum": (q8.replace("set Scheme = HRZ", "set Scheme = row-sum"),
                   ["Mass matrix/Scheme", "row-sum", "negative corner masses"]),
    "q8_with_iga": (q8.replace("set Method             = fea", "set Method             = iga"),
                    ["Discretization/FEA element", "serendipity", "Method = fea"]),
})
for name, (text, words) in cases.items():
    prm = os.path.join(workdir, name + ".prm")
    with open(prm, "w") as f:
        f.write(text)
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
