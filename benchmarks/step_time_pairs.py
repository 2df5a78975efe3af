#!/usr/bin/env python3
"""One scene run whole under two command prefixes in turns (A, B, A, B,
...), each run's median step read from its step_times.csv: for what acts
on a whole process and cannot be switched within one, such as the address
space's randomisation (`setarch -R`), a core binding (`taskset`) or an
environment variable. Whole runs see the machine at different minutes;
only the sign of B/A over many pairs tells (doc/parallel.md, session 55).

The scene is that of alternating_runs.py (the Hertz benchmark at about 1e6
unknowns, `Output/Step times = true`); the median skips the first 50 steps.

usage: python3 benchmarks/step_time_pairs.py [--method "FEA Q9"|"IGA p2"]
          [--level L] [--steps 400] [--threads 2] [--ranks 1] [--pairs 6]
          [--build build] --a "PREFIX" --b "PREFIX"
  --a, --b: a command prefix ('' for none), e.g. --a '' --b 'setarch -R'.
  prints each run's median step [ms], each pair's B/A and their median."""
import argparse
import csv
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "benchmarks"))
from alternating_runs import scene  # noqa: E402
from mpi_step_cost import CASES  # noqa: E402


def median_step(folder, skip=50):
    with open(os.path.join(folder, "step_times.csv")) as table:
        clock = [float(row["monotonic_clock_s"]) for row in csv.DictReader(table)]
    steps = [b - a for a, b in zip(clock[skip:], clock[skip + 1:])]
    if not steps:
        sys.exit(f"{folder}: fewer than {skip + 2} steps")
    return statistics.median(steps)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--method", choices=list(CASES), default="FEA Q9")
    parser.add_argument("--level", type=int)
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--pairs", type=int, default=6)
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--a", required=True, metavar="PREFIX")
    parser.add_argument("--b", required=True, metavar="PREFIX")
    args = parser.parse_args()
    program = os.path.join(os.path.abspath(args.build), "isoimpact")
    if not os.access(program, os.X_OK):
        sys.exit(f"{program}: not built")
    work = tempfile.mkdtemp(prefix="step_time_pairs_")
    prm = scene(args.method, args.level, args.steps, work, "run", {})
    command = [program, prm]
    if args.ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "-np", str(args.ranks),
                   "-x", "DEAL_II_NUM_THREADS"] + command
    env = {**os.environ, "DEAL_II_NUM_THREADS": str(args.threads)}
    ratios = []
    try:
        run_pairs(args, command, env, work, ratios)
    finally:
        shutil.rmtree(work)  # also where a run failed
    print(f"B/A: median {statistics.median(ratios):.3f} over {len(ratios)} pairs, "
          f"below 1 in {sum(r < 1 for r in ratios)}; A = {args.a!r}, B = {args.b!r}")


def run_pairs(args, command, env, work, ratios):
    for pair in range(args.pairs):
        times = []
        for prefix in (args.a, args.b):
            result = subprocess.run(shlex.split(prefix) + command, cwd=work, env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if result.returncode != 0:
                sys.exit(f"{prefix!r}: exit {result.returncode}\n{result.stderr[-2000:]}")
            times.append(median_step(os.path.join(work, "run")))
        ratios.append(times[1] / times[0])
        print(f"pair {pair + 1}: A {1e3 * times[0]:.3f} ms, B {1e3 * times[1]:.3f} ms, "
              f"B/A {ratios[-1]:.3f}", flush=True)


if __name__ == "__main__":
    main()
