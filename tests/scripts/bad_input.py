"""Bad parameter files (issue 10): a table of malformed files derived from a
good one, each of which must exit with 2 (no signal), a message naming the
file and the given words (the parameter, the value, what is allowed), and
leave no output directory. The table holds at least 50 cases; the count is
asserted. Then the missing file, --print-parameters and --help."""
import os
import shutil
import subprocess
import sys

from testing import check_true, edit_prm, report

program, good_prm, workdir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(workdir, exist_ok=True)
base = {"Output/Directory": "bad_output"}
good_text = open(good_prm).read()
no_reference = {"Output/Analytic reference": "none"}
plane = {"Obstacle/Type": "plane", "Obstacle/Penalty": "2e5"}
cylinder = {"Obstacle/Type": "cylinder", "Obstacle/Center": "0, -4", "Obstacle/Radius": "4",
            "Obstacle/Penalty": "2e5"}
channel = {"Obstacle/Type": "channel", "Obstacle/Penalty": "2e5", **no_reference}
E = "Body 1/Material/Young's modulus"

# name: (edits of the good file, or the text of the file, [words of the message])
cases = {
    "unknown_key": ({"Contact/Penalty per pass": None, "Contact/Penalty per passage": "half"},
                    ["Penalty per passage"]),
    "wrong_type": ({"Time integration/Time step": "fast"}, ["Time step", "fast"]),
    "out_of_range": ({"Body 1/Material/Poisson's ratio": "0.7"}, ["Poisson's ratio", "0.7"]),
    "negative_modulus": ({E: "-5"}, ["Young's modulus", "-5"]),
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
# Mass redistribution (Contact/Mass redistribution) with what it does not
# support.
redistribute = {"Contact/Mass redistribution": "true"}
cases.update({
    "redistribution_consistent": ({**redistribute, "Mass matrix/Scheme": "consistent"},
                                  ["Mass matrix/Scheme", "consistent", "lumped mass"]),
    "redistribution_damping": ({**redistribute, "Contact/Damping ratio": "0.2"},
                               ["Contact/Damping ratio", "0.2", "Mass redistribution"]),
    "redistribution_local_refinement": ({**redistribute,
                                         "Discretization/Local refinements": "1"},
                                        ["Local refinements", "1", "hanging nodes"]),
    "redistribution_bipenalty": ({**redistribute, "Contact/Bipenalty": "true"},
                                 ["Contact/Bipenalty", "true", "Mass redistribution"]),
})
# The file itself: empty, keys set twice (deal.II would take the last),
# broken structure.
empty = ["sets no parameter", "--print-parameters"]
cases.update({
    "empty_file": ("", empty),
    "only_comments": ("# a parameter file\n\n   # nothing set\n", empty),
    "only_subsections": ("subsection Body 1\n  subsection Material\n  end\nend\n", empty),
    "duplicate_key": (good_text + "subsection Time integration\n  set End time = 0.5\nend\n",
                      ["'Time integration/End time'", "set twice", "'0.9'", "'0.5'", "remove one"]),
    "duplicate_nested_key": (good_text + "subsection Body 1\n subsection Material\n"
                             "  set Young's   modulus = 2000\n end\nend\n",
                             ["'Body 1/Material/Young's modulus'", "set twice", "'1000'", "'2000'"]),
    "duplicate_key_same_value": (good_text.replace("set Penalty                    = 1e5",
                                                   "set Penalty = 1e5\n  set Penalty = 1e5"),
                                 ["'Contact/Penalty'", "set twice"]),
    "unknown_subsection": ({"Body 3/Radius": "4"}, ["Body 3"]),
    "missing_end": (good_text + "subsection Obstacle\n  set Type = none\n",
                    ["unequal numbers of 'subsection' and 'end'"]),
    "line_without_set": (good_text.replace("set Radius           = 4", "Radius = 4", 1),
                         ["Radius = 4"]),
})
# Wrong types and values outside the patterns' ranges.
cases.update({
    "degree_word": ({"Discretization/Degree": "two"}, ["Degree", "two"]),
    "degree_7": ({"Discretization/Degree": "7"}, ["Degree", "7"]),
    "global_refinements_negative": ({"Discretization/Global refinements": "-1"},
                                    ["Global refinements", "-1"]),
    "global_refinements_11": ({"Discretization/Global refinements": "11"},
                              ["Global refinements", "11"]),
    "local_refinements_11": ({"Discretization/Local refinements": "11"},
                             ["Local refinements", "11"]),
    "quadrature_points_0": ({"Contact/Quadrature points per face": "0"},
                            ["Quadrature points per face", "0"]),
    "history_interval_0": ({"Output/History interval": "0"}, ["History interval", "0"]),
    "vtu_subdivisions_9": ({"Output/VTU subdivisions": "9"}, ["VTU subdivisions", "9"]),
    "progress_interval_150": ({"Output/Progress interval": "150"}, ["Progress interval", "150"]),
    "safety_factor_1.5": ({"Time integration/Time step safety factor": "1.5"},
                          ["Time step safety factor", "1.5"]),
    "safety_factor_0": ({"Time integration/Time step safety factor": "0"},
                        ["Time step safety factor", "(0, 1]"]),
    "center_one_number": ({"Body 1/Center": "4"}, ["Center", "4"]),
    "center_three_numbers": ({"Body 1/Center": "0, 4, 1"}, ["Center", "0, 4, 1"]),
    "velocity_words": ({"Body 1/Initial velocity": "down"}, ["Initial velocity", "down"]),
    "symmetry_cut_maybe": ({"Body 1/Symmetry cut": "maybe"}, ["Symmetry cut", "maybe"]),
    "plane_membrane": ({"Model/Plane": "membrane"}, ["Plane", "membrane"]),
    "method_fem": ({"Discretization/Method": "fem"}, ["Method", "fem"]),
    "reference_hertz": ({"Output/Analytic reference": "Hertz"}, ["Analytic reference", "Hertz"]),
    "penalty_per_pass_double": ({"Contact/Penalty per pass": "double"},
                                ["Penalty per pass", "double"]),
    "shape_square": ({"Body 1/Shape": "square"}, ["Shape", "square"]),
    "time_step_negative": ({"Time integration/Time step": "-1e-4"}, ["Time step", "-1e-4"]),
    "time_step_zero": ({"Time integration/Time step": "0"}, ["Time step", "positive or auto"]),
    "end_time_zero": ({"Time integration/End time": "0"}, ["End time", "positive"]),
    "time_step_above_end_time": ({"Time integration/Time step": "1",
                                  "Time integration/End time": "0.5"},
                                 ["Time step", "not exceed the end time"]),
    "profile_time_negative": ({"Output/Pressure profile times": "-0.1"},
                              ["Pressure profile times", "-0.1"]),
    "density_zero": ({"Body 2/Material/Density": "0"}, ["Body 2/Material/Density", "positive"]),
    "modulus_zero": ({E: "0"}, ["Young's modulus", "positive"]),
    "poisson_minus_1": ({"Body 1/Material/Poisson's ratio": "-1"}, ["Poisson's ratio", "(-1, 0.5)"]),
    "poisson_0.5": ({"Body 2/Material/Poisson's ratio": "0.5"}, ["Poisson's ratio", "(-1, 0.5)"]),
    "rectangle_inverted": ({"Body 1/Shape": "rectangle", "Body 1/Lower left corner": "0, 1",
                            "Body 1/Upper right corner": "1, 0", **no_reference},
                           ["Upper right corner", "exceed the lower left"]),
    "rectangle_with_reference": ({"Body 1/Shape": "rectangle", "Body 1/Lower left corner": "-1, 0",
                                  "Body 1/Upper right corner": "1, 1"},
                                 ["Body 1/Shape", "rectangle", "needs disks"]),
    "channel_with_reference": ({**channel, "Output/Analytic reference": "Gerl-Zippelius"},
                               ["Output/Analytic reference", "a channel has no analytic"]),
    "channel_opposite_behind": ({**channel, "Obstacle/Opposite point": "0, -10"},
                                ["Obstacle/Opposite point", "(0, -10)", "side"]),
})
# Values of valid form beyond what the program carries through.
cases.update({
    "modulus_1e308": ({E: "1e308"}, ["Body 1/Material/Young's modulus", "1e+308", "[1e-06, 1e+15] Pa"]),
    "modulus_1e-300": ({E: "1e-300"}, ["Young's modulus", "1e-300", "[1e-06, 1e+15]"]),
    "density_1e300": ({"Body 2/Material/Density": "1e300"},
                      ["Body 2/Material/Density", "1e+300", "[1e-06, 1e+09] kg/m^3"]),
    "radius_1e300": ({"Body 1/Radius": "1e300"}, ["Body 1/Radius", "1e+300", "[1e-09, 1e+09] m"]),
    "radius_1e-300": ({"Body 2/Radius": "1e-300"}, ["Body 2/Radius", "1e-300", "[1e-09, 1e+09] m"]),
    "center_1e10": ({"Body 1/Center": "0, 1e10"}, ["Body 1/Center", "(0, 1e+10)", "4e+06 m of the origin"]),
    "rectangle_far_away": ({"Body 1/Shape": "rectangle", "Body 1/Lower left corner": "1e12, 0",
                            "Body 1/Upper right corner": "1e12, 1", **no_reference},
                           ["Upper right corner", "exceed the lower left"]),
    "velocity_1e300": ({"Body 1/Initial velocity": "0, -1e300", **no_reference},
                       ["Body 1/Initial velocity", "1e+300", "1e8 m/s"]),
    "penalty_1e300": ({"Contact/Penalty": "1e300"}, ["Contact/Penalty", "1e+300", "[1e-06, 1e+20] Pa/m"]),
    "obstacle_penalty_1e300": ({**plane, "Obstacle/Penalty": "1e300"},
                               ["Obstacle/Penalty", "1e+300", "[1e-06, 1e+20]"]),
    "obstacle_radius_1e300": ({**cylinder, "Obstacle/Radius": "1e300"},
                              ["Obstacle/Radius", "1e+300", "[1e-09, 1e+09] m"]),
    "refinement_center_1e10": ({"Discretization/Local refinements": "1",
                                "Discretization/Refinement center": "1e10, 0"},
                               ["Discretization/Refinement center", "(1e+10, 0)", "origin"]),
    "filter_window_1e300": ({"Output/Filter window": "1e300"},
                            ["Output/Filter window", "1e+300", "10 times the end time"]),
        "obstacle_point_1e10": ({**plane, "Obstacle/Point": "0, 1e10"},
                            ["Obstacle/Point", "(0, 1e+10)", "origin"]),
})
# Scenes the patterns cannot see: overlaps, a body inside an obstacle, a
# reference that does not describe the scene.
way_out = "Analytic reference = none"
cases.update({
    "bodies_overlap": ({"Body 1/Center": "0, 3.5"},
                       ["Body 1 and Body 2 overlap", "'Body 1/Center' = (0, 3.5)",
                        "'Body 2/Center' = (0, -4)", "move them apart"]),
    "bodies_overlap_no_reference": ({"Body 1/Center": "0, 3.9", **no_reference},
                                    ["overlap", "(0, 3.9)", "0.0975682 m inside Body 2", "move them apart"]),
    "body_inside_body": ({"Body 2/Shape": "full disk", "Body 2/Center": "2, 4",
                          "Body 2/Radius": "1", **no_reference},
                         ["overlap", "inside Body 1", "'Body 2/Radius' = 1"]),
    "rectangle_overlaps_disk": ({"Body 2/Shape": "rectangle", "Body 2/Lower left corner": "-1, -1",
                                 "Body 2/Upper right corner": "1, 0.5", **no_reference},
                                ["overlap", "'Body 2/Upper right corner' = (1, 0.5)"]),
    "body_inside_plane": ({**plane, "Body 1/Center": "0, 3"},
                          ["Body 1 starts inside the rigid plane", "1 m behind",
                           "'Obstacle/Point' = (0, 0)", "'Body 1/Center' = (0, 3)"]),
    "body_behind_plane": ({**plane, "Obstacle/Normal": "0, -1", **no_reference},
                          ["inside the rigid plane", "'Obstacle/Normal' = (0, -1)", "8 m behind"]),
    "body_inside_cylinder": ({**cylinder, "Body 1/Center": "0, 3"},
                             ["Body 1 starts inside the rigid cylinder", "'Obstacle/Radius' = 4",
                              "'Body 1/Center' = (0, 3)"]),
    "cylinder_inside_body": ({**cylinder, "Obstacle/Center": "1.5, 4", "Obstacle/Radius": "1",
                              **no_reference},
                             ["rigid cylinder", "'Obstacle/Center' = (1.5, 4)", "centre 1.5 m inside Body 1"]),
    "channel_too_narrow": ({**channel, "Obstacle/Opposite point": "0, 7"},
                           ["second plane of the channel", "(0, 7)", "1 m behind"]),
    "reference_gap": ({"Body 1/Center": "0, 4.5"},
                      ["touch at t = 0", "0.5 m apart", "'Body 1/Center' = (0, 4.5)", way_out]),
    "reference_moving_apart": ({"Body 1/Initial velocity": "0, 2", "Body 2/Initial velocity": "0, -2"},
                               ["line of centres", "'Body 1/Initial velocity' = (0, 2)", way_out]),
    "reference_oblique": ({"Body 1/Initial velocity": "1, -2"},
                          ["line of centres", "(1, -4)", way_out]),
    "reference_plane_gap": ({**plane, "Body 1/Center": "0, 5"},
                            ["touching the rigid plane", "1 m from it", way_out]),
    "reference_plane_beside_the_cut": ({**plane, "Obstacle/Point": "-4, 4", "Obstacle/Normal": "1, 0",
                                        "Body 1/Initial velocity": "-2, 0"},
                                       ["not on the half disk's arc", "'Obstacle/Normal' = (1, 0)",
                                        way_out]),
        "reference_cylinder_gap": ({**cylinder, "Obstacle/Center": "0, -5"},
                               ["the rigid cylinder are 1 m apart", way_out]),
    "closing_speed_above_limit": ({"Body 1/Initial velocity": "0, -2000",
                                   "Body 2/Initial velocity": "0, 2000"},
                                  ["'Body 1/Initial velocity' = (0, -2000)",
                                   "closing speed must be below 19.24", way_out]),
})
# Time: absurd step counts (a 32-bit count wrapped End 4294.967306 s at
# dt 1e-6 s to 10 steps).
cases.update({
    "end_time_1e300": ({"Time integration/End time": "1e300"},
                       ["'Time integration/End time' = 1e+300", "2e+303 steps", "at most 1e+08"]),
    "time_step_1e-300": ({"Time integration/Time step": "1e-300"},
                         ["'Time integration/Time step' = 1e-300", "9e+299 steps", "at most 1e+08"]),
    "step_count_beyond_32_bits": ({"Time integration/End time": "4294.967306",
                                   "Time integration/Time step": "1e-6"},
                                  ["4.29497e+09 steps", "at most 1e+08"]),
    "end_time_1e300_auto_step": ({"Time integration/End time": "1e300",
                                  "Time integration/Time step": "auto"},
                                 ["auto (", "of the stable step bound", "at most 1e+08"]),
})
# Memory: refinements inside the allowed ranges that no machine holds.
cases.update({
    "global_refinements_10": ({"Discretization/Global refinements": "10"},
                              ["'Discretization/Global refinements' = 10", "8.39e+06 cells",
                               "MemAvailable", "fewer refinements"]),
    "local_refinements_10": ({"Discretization/Local refinements": "10"},
                             ["'Discretization/Local refinements' = 10", "MemAvailable"]),
    "iga_global_refinements_10": ({"Discretization/Method": "iga",
                                   "Discretization/Global refinements": "10"},
                                  ["Global refinements' = 10", "iga", "MemAvailable"]),
})

for name, (edits, words) in cases.items():
    prm = os.path.join(workdir, name + ".prm")
    if isinstance(edits, str):
        with open(prm, "w") as f:
            f.write(edits)
    else:
        edit_prm(good_prm, prm, {**base, **edits})
    shutil.rmtree(os.path.join(workdir, "bad_output"), ignore_errors=True)
    run = subprocess.run([program, prm], cwd=workdir, capture_output=True, text=True)
    message = run.stderr
    print(f"--- {name}: exit {run.returncode}\n{message.strip()}")
    check_true(f"{name}: exit 2 (bad input, no signal)", run.returncode == 2)
    check_true(f"{name}: message names the file", prm in message)
    for word in words:
        check_true(f"{name}: message names '{word}'", word in message)
    check_true(f"{name}: no output directory", not os.path.exists(os.path.join(workdir, "bad_output")))
check_true(f"{len(cases)} malformed parameter files (at least 50)", len(cases) >= 50)

missing = os.path.join(workdir, "does_not_exist.prm")
run = subprocess.run([program, missing], cwd=workdir, capture_output=True, text=True)
check_true("missing file: exit 2", run.returncode == 2)
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
# Into a full device: exit 1 with a message, no SIGABRT.
if os.path.exists("/dev/full"):
    with open("/dev/full", "w") as full:
        run = subprocess.run([program, "--print-parameters"], stdout=full, stderr=subprocess.PIPE,
                             text=True)
    print(f"--- --print-parameters > /dev/full: exit {run.returncode}\n{run.stderr.strip()}")
    check_true("--print-parameters > /dev/full: exit 1, no signal", run.returncode == 1)
    check_true("--print-parameters > /dev/full: says the write failed",
               "writing the default parameters" in run.stderr and "failed" in run.stderr)
# Several MPI ranks: bad input is refused by every rank alike, said once (by
# rank 0), with the file and the parameter named (exit 2), and no output is
# written: a time step above the stable bound. The runs that work on 2 ranks
# (every scene, since session 14) are checked by mpi_history.py.
mpirun = shutil.which("mpirun")
check_true("mpirun is installed (scripts/setup.sh installs openmpi-bin)", mpirun is not None)
if mpirun:
    too_large = os.path.join(workdir, "time_step_for_mpi.prm")
    edit_prm(good_prm, too_large, {"Output/Directory": "mpi_output",
                                   "Time integration/Time step": "0.01"})
    shutil.rmtree(os.path.join(workdir, "mpi_output"), ignore_errors=True)
    run = subprocess.run([mpirun, "--allow-run-as-root", "--oversubscribe", "-np", "2", program,
                          too_large], cwd=workdir, capture_output=True, text=True)
    print(f"--- mpirun -np 2, time step 0.01 s: exit {run.returncode}\n{run.stderr.strip()[:600]}")
    check_true("mpirun -np 2, time step above the bound: exit 2", run.returncode == 2)
    check_true("mpirun -np 2, time step above the bound: message names the file, the "
               "parameter and its value",
               too_large in run.stderr and "Time step" in run.stderr and "0.01" in run.stderr)
    check_true("mpirun -np 2, time step above the bound: said once (by rank 0)",
               run.stderr.count(too_large) == 1)
    check_true("mpirun -np 2, time step above the bound: no output directory",
               not os.path.exists(os.path.join(workdir, "mpi_output")))
run = subprocess.run([program, "--help"], capture_output=True, text=True)
check_true("--help exits with 0 and shows usage", run.returncode == 0 and "usage" in run.stdout)
report()
