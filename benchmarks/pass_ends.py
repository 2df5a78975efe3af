#!/usr/bin/env python3
"""How far apart the two ranks' passes end (issue 13, doc/parallel.md
session 56).

A 2-rank run with load balancing writes pass_times.csv: per step, where each
rank's pass ended on the machine's monotonic clock (one clock for both
processes). The rank whose pass ends first waits for the other before the
contact (the claims of a band, Load balancing = shared memory, should end
both passes together); a perfect split of the same work would end both at
the mean of the two ends, so the step loses half the difference. Printed
per file, over the steps after --skip: the median, mean and deciles of
|end_0 - end_1| [us], and half its mean as the step's loss [us per step].

usage: python3 benchmarks/pass_ends.py [--skip 50] PASS_TIMES_CSV ...
       python3 benchmarks/pass_ends.py --run FILE.prm [--build build] [--env VARIABLE=VALUE]
  --run: runs FILE.prm on 2 ranks x 1 thread (mpirun) into a temporary
  folder first and reads its pass_times.csv (removed afterwards)."""
import argparse
import csv
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from testing import edit_prm  # noqa: E402


def describe(path, skip, label=None):
    with open(path) as file:
        rows = list(csv.DictReader(file))
    if not rows or "rank_0_pass_end_s" not in rows[0]:
        sys.exit(f"{path}: no column rank_0_pass_end_s (a pass_times.csv of a "
                 f"build from session 56 on is needed)")
    rows = rows[skip:]
    if len(rows) < 10:
        sys.exit(f"{path}: {len(rows)} passes after the first {skip}; at least 10 needed")
    gaps = [1e6 * abs(float(r["rank_0_pass_end_s"]) - float(r["rank_1_pass_end_s"]))
            for r in rows]
    deciles = statistics.quantiles(gaps, n=10)
    print(f"{label or path}: {len(gaps)} passes; |end_0 - end_1| [us]: median "
          f"{statistics.median(gaps):.1f}, mean {statistics.mean(gaps):.1f}, deciles "
          + " ".join(f"{d:.1f}" for d in deciles)
          + f"; the step's loss (half the mean) {statistics.mean(gaps) / 2:.1f} us per step")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="*", metavar="PASS_TIMES_CSV")
    parser.add_argument("--skip", type=int, default=50,
                        help="passes left out at the start (page faults, the balancing's start)")
    parser.add_argument("--run", metavar="FILE.prm")
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--env", action="append", default=[], metavar="VARIABLE=VALUE")
    args = parser.parse_args()
    if not args.files and not args.run:
        parser.error("give PASS_TIMES_CSV files or --run FILE.prm")
    for path in args.files:
        describe(path, args.skip)
    if args.run:
        program = os.path.join(args.build, "isoimpact")
        if not os.path.exists(program):
            sys.exit(f"{program} does not exist: build first (or give --build)")
        work = tempfile.mkdtemp(prefix="pass_ends_")
        try:
            prm = edit_prm(os.path.abspath(args.run), os.path.join(work, "run.prm"),
                           {"Output/Directory": "out", "Output/VTU interval": "0"})
            command = ["mpirun", "--allow-run-as-root", "-np", "2", "-x",
                       "DEAL_II_NUM_THREADS=1"]
            for setting in args.env:
                command += ["-x", setting]
            done = subprocess.run(command + [program, prm], cwd=work,
                                  capture_output=True, text=True)
            if done.returncode != 0:
                sys.exit(f"the run failed ({done.returncode}):\n{done.stdout[-2000:]}"
                         f"{done.stderr[-2000:]}")
            path = os.path.join(work, "out", "pass_times.csv")
            if not os.path.exists(path):
                sys.exit(f"{args.run}: no pass_times.csv (2 ranks with load balancing needed)")
            describe(path, args.skip, f"{args.run} on 2 ranks")
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
