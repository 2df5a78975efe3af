#!/usr/bin/env python3
"""How much of a 2-rank step the load balancing can still win, from the
ranks' recorded pass times (issue 13, doc/parallel.md session 37).

A 2-rank run with measured load balancing writes pass_times.csv: per step,
each rank's time of its pass over its owned rows [s] and their number. A
rank's time per row changes from step to step (its core, the other rank's
memory traffic, the host); the step waits for the slower pass. Replayed on
the same recorded times per row, each rule below gives the sum over the
steps of the slower pass, max(c0 n0, c1 n1), with n0 + n1 the recorded rows,
in % above the per-step oracle (each step split by its own times, which no
rule that reads past steps can reach):
- none: the partition's split kept;
- best static: the best fixed split in hindsight;
- rule 36: the rule up to session 36 (a first move after 20 steps, then at
  least 20 steps between moves; an exponential average of weight 0.05
  started at the sixth step's value; a move for a predicted 2 %);
- rule 37: the committed rule (source/discretization/unknown_exchange.cc:
  the mean of the steps after the third, then weight 0.05; a move after 5
  such steps and at least 10 steps between moves; 2 %);
- follower: the mean of the last 10 steps, every step, without bounds or
  cost (how far any rule on past steps' averages gets).
The replay splits rows continuously (the program moves whole interface
layers, about 0.1-0.2 % of the rows each), bounds rank 0's rows as the
program does (15 % of each part's rows of a split body, 30 % of each body
of bodies whole on ranks: doc/parallel.md sessions 17 and 31), counts
1 ms per move (session 36: 0.37-1.22 ms) and makes a move chosen after step
n effective from step n + 2 (moves without a meeting). The first three
steps (page faults) are left out of every sum.

usage: python3 benchmarks/balance_replay.py [--steps 800] [--runs 1] [--slow-core 30]
                                           [--build build] [--window 200] [--keep DIR] [CSV ...]
  Without CSV files it runs FEA Q9 level 7 and IGA p2 level 8 (as
  benchmarks/mpi_step_cost.py --fine) on 2 ranks x 1 thread, --runs times
  each with equal cores and with a competing process on core 0 busy
  --slow-core % of every 10 ms (a slower core for rank 0, which mpirun binds
  to core 0), and replays their pass_times.csv. --window: the sums also
  over windows of that many steps (the speed benchmark's runs are 200).
  --keep DIR: the runs' pass_times.csv are copied there (to replay again)."""
import argparse
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "benchmarks"))
from mpi_step_cost import benchmark_prm  # noqa: E402

CASES = {"FEA Q9 level 7": ("prm/hertz_fea_hrz.prm", 7),
         "IGA p2 level 8": ("prm/hertz_iga_hrz.prm", 8)}
SKIPPED = 3          # first steps left out of the sums
MOVE_COST = 1e-3     # s per move
MOVE_LAG = 2         # a move chosen after step n is effective from step n + 2
# Movable fraction of each part's rows (doc/parallel.md, sessions 17 and 31).
BAND = {"split": 0.15, "bodies whole on ranks": 0.30}
GAIN = 0.02          # least predicted gain of a move


def read_passes(path):
    """{balanced: [(c0, c1, n0, n1)]}: times per row [s] and rows."""
    groups = {}
    with open(path) as file:
        for row in csv.DictReader(file):
            rows = (float(row["rank_0_rows"]), float(row["rank_1_rows"]))
            groups.setdefault(row["balanced"], []).append(
                (float(row["rank_0_pass_s"]) / max(rows[0], 1.),
                 float(row["rank_1_pass_s"]) / max(rows[1], 1.)) + rows)
    return groups


def slower_pass(c, n0, total):
    return max(c[0] * n0, c[1] * (total - n0))


def best_split(c, total, low, high):
    """Rank 0's rows that equal the ranks' predicted passes, in bounds."""
    return min(max(total * c[1] / (c[0] + c[1]), low), high)


def bounds(passes, band):
    """Rank 0's least and most rows: `band` (the movable fraction of each
    part's rows) around the first pass's rows, the partition's split."""
    return (passes[0][2] * (1. - band), passes[0][2] + band * passes[0][3])


def replay_rule(passes, limits, skipped, least_averaged, least_between, mean_start):
    """The program's rule on recorded times: (sum of slower passes [s],
    moves)."""
    total = passes[0][2] + passes[0][3]
    n0 = passes[0][2]
    low, high = limits
    estimate, averaged, last_move, observations = [0., 0.], 0, None, 0
    pending, moves, time = None, 0, 0.
    for step, (c0, c1, _, _) in enumerate(passes):
        if pending and pending[0] == step:
            n0, pending, moves = pending[1], None, moves + 1
            time += MOVE_COST
        if step >= SKIPPED:
            time += slower_pass((c0, c1), n0, total)
        if pending:
            continue  # no split is chosen while a move is under way
        observations += 1
        if observations <= skipped:
            continue
        averaged += 1
        weight = max(1. / averaged, 0.05) if mean_start else (1. if averaged == 1 else 0.05)
        estimate = [e + weight * (c - e) for e, c in zip(estimate, (c0, c1))]
        if averaged < least_averaged or (last_move is not None and
                                         observations < last_move + least_between):
            continue
        best = best_split(estimate, total, low, high)
        if slower_pass(estimate, best, total) < (1. - GAIN) * slower_pass(estimate, n0, total):
            pending, last_move = (step + MOVE_LAG, best), observations
    return time, moves


def replay(passes, limits):
    """{rule: sum of the slower passes [s]} and the rules' moves, from the
    first pass's split within `limits` (rank 0's least and most rows)."""
    total = passes[0][2] + passes[0][3]
    counted = passes[SKIPPED:]
    n0 = passes[0][2]
    low, high = limits
    sums = {"oracle": sum(total / (1. / c0 + 1. / c1) for c0, c1, _, _ in counted),
            "none": sum(slower_pass(p, n0, total) for p in counted)}
    candidates = [low + (high - low) * k / 400. for k in range(401)]
    sums["best static"] = min(sum(slower_pass(p, x, total) for p in counted)
                              for x in candidates)
    moves = {}
    sums["rule 36"], moves["rule 36"] = replay_rule(passes, limits, 5, 15, 20, False)
    sums["rule 37"], moves["rule 37"] = replay_rule(passes, limits, 3, 5, 10, True)
    follower = 0.
    for step in range(SKIPPED, len(passes)):
        past = passes[max(0, step - MOVE_LAG - 9):max(1, step - MOVE_LAG + 1)]
        mean = [statistics.fmean(p[k] for p in past) for k in (0, 1)]
        follower += slower_pass(passes[step], total * mean[1] / (mean[0] + mean[1]), total)
    sums["follower"] = follower
    return sums, moves


def describe(label, passes, band):
    ratios = [c0 / c1 for c0, c1, _, _ in passes[SKIPPED:]]
    mean = statistics.fmean(ratios)
    lag1 = (statistics.correlation(ratios[:-1], ratios[1:])
            if hasattr(statistics, "correlation") and len(ratios) > 2 else float("nan"))
    sums, moves = replay(passes, bounds(passes, band))
    oracle = sums["oracle"]
    above = " | ".join(f"{100. * (sums[k] / oracle - 1.):.1f}" for k in
                       ("none", "best static", "rule 36", "rule 37", "follower"))
    print(f"| {label} | {len(passes)} | "
          f"{1e9 * statistics.median(p[0] for p in passes):.1f}/"
          f"{1e9 * statistics.median(p[1] for p in passes):.1f} | {mean:.3f} | "
          f"{statistics.pstdev(ratios):.3f} | {lag1:.2f} | {oracle:.3f} | {above} | "
          f"{moves['rule 36']}/{moves['rule 37']} |", flush=True)
    return sums


def header():
    print("| run | steps | time per row, rank 0/1 [ns] (median) | ratio rank 0/1 (mean) | "
          "its s.d. per step | its lag-1 autocorrelation | oracle: slower passes [s] | "
          "none [% above oracle] | best static [%] | rule 36 [%] | rule 37 [%] | follower [%] | "
          "moves, rule 36/37 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def run_cases(args, work):
    program = os.path.join(args.build, "isoimpact")
    for tool in ("mpirun", "taskset"):
        if not shutil.which(tool):
            sys.exit(f"{tool} is needed (Debian: apt-get install openmpi-bin util-linux)")
    files = []
    for name, (prm, level) in CASES.items():
        edited = benchmark_prm(prm, level, args.steps, work)
        for run in range(args.runs):
            for slow in (0, args.slow_core):
                competitor = None
                if slow > 0:
                    busy = slow / 100. * 0.01
                    competitor = subprocess.Popen(
                        ["taskset", "-c", "0", sys.executable, "-c",
                         "import time\nwhile True:\n t = time.perf_counter()\n"
                         f" while time.perf_counter() - t < {busy}: pass\n"
                         f" time.sleep({0.01 - busy})"])
                try:
                    out = os.path.join(work, "out")
                    shutil.rmtree(out, ignore_errors=True)
                    subprocess.run(["mpirun", "--allow-run-as-root", "--bind-to", "core", "-np", "2",
                                    "-x", "DEAL_II_NUM_THREADS=1", program, edited],
                                   cwd=work, check=True, stdout=subprocess.DEVNULL)
                finally:
                    if competitor:
                        competitor.kill()
                        competitor.wait()
                label = f"{name}, run {run + 1}, " + (
                    f"core 0 shared ({slow} %)" if slow > 0 else "equal cores")
                kept = os.path.join(work, f"passes_{len(files)}.csv")
                shutil.copy(os.path.join(out, "pass_times.csv"), kept)
                files.append((label, kept))
                if args.keep:
                    os.makedirs(args.keep, exist_ok=True)
                    shutil.copy(kept, os.path.join(args.keep, re.sub(r"[^A-Za-z0-9]+", "_", label)
                                                   + ".csv"))
    return files


def main():
    parser = argparse.ArgumentParser(usage=__doc__)
    parser.add_argument("csv", nargs="*")
    parser.add_argument("--steps", type=int, default=800)
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--slow-core", type=int, default=30)
    parser.add_argument("--window", type=int, default=200)
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--keep")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        files = ([(path, path) for path in args.csv] if args.csv else run_cases(args, work))
        header()
        windows = []
        for label, path in files:
            for balanced, passes in read_passes(path).items():
                name = f"{label} ({balanced})"
                band = BAND.get(balanced, BAND["split"])
                describe(name, passes, band)
                for start in range(0, len(passes) - args.window + 1, args.window):
                    sums, _ = replay(passes[start:start + args.window],
                                     bounds(passes, band))
                    windows.append((start, sums["rule 36"] / sums["oracle"] - 1.,
                                    sums["rule 37"] / sums["oracle"] - 1.))
        print()
        for which, chosen in (("all windows", windows),
                              ("first windows (the runs' first steps)",
                               [w for w in windows if w[0] == 0])):
            if not chosen:
                continue
            better = sum(1 for _, old, new in chosen if new < old)
            gains = sorted(100. * (old - new) for _, old, new in chosen)
            print(f"Windows of {args.window} steps, {which}: rule 37 below rule 36 in {better} "
                  f"of {len(chosen)}; rule 36 minus rule 37 [points of %]: median "
                  f"{statistics.median(gains):.1f}, range {gains[0]:.1f} to {gains[-1]:.1f}")


if __name__ == "__main__":
    main()
