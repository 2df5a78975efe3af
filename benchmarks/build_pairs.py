#!/usr/bin/env python3
"""Two builds of the program, run in turn on one scene (issue 13): PAIRS
pairs (A, B, A, B, ...) so that a drifting machine hits both, each on
--ranks MPI ranks with one thread per process. Per run, from summary.json:
the step (time loop less the initial acceleration, over the steps) and each
rank's time outside the bodies' passes per step (that less
passes_s_per_rank: contacts, waits, the step's end), in ms. Prints every
pair, then B - A of the ranks' mean time outside the passes (the median,
how many pairs B is lower in) and B / A of the step (the median).

A build is a build directory: its `isoimpact`, with its `libisoimpact.so`
first on the library path (the program's RUNPATH yields to
LD_LIBRARY_PATH), so that a copy of an earlier build directory runs its
own library.

usage: python3 benchmarks/build_pairs.py BUILD_A BUILD_B FILE.prm
         [--pairs 8] [--ranks 2] [--steps 400] [--set Section/Key=value ...]
  --steps: End time = steps x the Time step (which must be a number);
  the history every 100 steps, no ParaView output, pressure profiles or
  progress lines; --set edits the file further.
The numbers of doc/parallel.md, session 48: BUILD_A a copy of the build
directory at 15cdfa6, BUILD_B 58ee57e's, and
  FILE prm/hertz_fea_hrz.prm --pairs 14 --set "Discretization/Global
  refinements=7" --set "Time integration/Time step=3.125e-5"."""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from testing import edit_prm  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("build_a")
parser.add_argument("build_b")
parser.add_argument("prm")
parser.add_argument("--pairs", type=int, default=8)
parser.add_argument("--ranks", type=int, default=2)
parser.add_argument("--steps", type=int, default=400)
parser.add_argument("--set", action="append", default=[])
args = parser.parse_args()
edits = dict(edit.split("=", 1) for edit in args.set)

text = open(args.prm).read()
time_step = float(edits.get("Time integration/Time step") or
                  [line.split("=")[1] for line in text.splitlines()
                   if line.split("=")[0].split() == ["set", "Time", "step"]][-1])
work = tempfile.mkdtemp()
prm = edit_prm(args.prm, os.path.join(work, "run.prm"),
               {**edits, "Time integration/End time": repr(args.steps * time_step),
                "Output/History interval": "100", "Output/VTU interval": "0",
                "Output/Pressure profile times": "", "Output/Progress interval": "100",
                "Output/Directory": "out"})


def run(build):
    build = os.path.abspath(build)
    shutil.rmtree(os.path.join(work, "out"), ignore_errors=True)
    command = [os.path.join(build, "isoimpact"), prm]
    if args.ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(args.ranks),
                   "-x", "DEAL_II_NUM_THREADS", "-x", "LD_LIBRARY_PATH"] + command
    env = {**os.environ, "DEAL_II_NUM_THREADS": "1",
           "LD_LIBRARY_PATH": build + ":" + os.environ.get("LD_LIBRARY_PATH", "")}
    result = subprocess.run(command, cwd=work, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)}: exit {result.returncode}\n{result.stderr[-2000:]}")
    summary = json.load(open(os.path.join(work, "out", "summary.json")))
    loop = summary["wall_time_parts_s"]["time_loop"] - summary["initial_acceleration_s"]
    steps = summary["steps"]
    outside = [1e3 * (loop - p) / steps for p in summary["passes_s_per_rank"]]
    return 1e3 * loop / steps, outside


rest_differences, step_ratios = [], []
for pair in range(args.pairs):
    step_a, outside_a = run(args.build_a)
    step_b, outside_b = run(args.build_b)
    rest_differences.append(statistics.mean(outside_b) - statistics.mean(outside_a))
    step_ratios.append(step_b / step_a)
    print(f"pair {pair + 1}: A step {step_a:.3f} ms, outside the passes "
          f"{' '.join(f'{x:.3f}' for x in outside_a)} ms; B step {step_b:.3f} ms, "
          f"outside the passes {' '.join(f'{x:.3f}' for x in outside_b)} ms", flush=True)
print(f"B - A, outside the passes per step (ranks' mean) [ms]: "
      f"{', '.join(f'{x:+.3f}' for x in rest_differences)}; median "
      f"{statistics.median(rest_differences):+.3f}, B lower in "
      f"{sum(x < 0 for x in rest_differences)} of {len(rest_differences)}")
print(f"B / A, step: {', '.join(f'{x:.3f}' for x in step_ratios)}; median "
      f"{statistics.median(step_ratios):.3f}")
shutil.rmtree(work)
