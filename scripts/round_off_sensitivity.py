#!/usr/bin/env python3
"""How much of a run's result is round-off: runs a scene N times with the
initial velocity of body 1 scaled by 1 + k * relative (k = 0 ... N-1; a
change at the level of round-off, 1e-12 by default) and prints, per run and
as the range over the runs, the measures of scripts/contact_measures.py
(force trend peak, chatter, energy error) with summary.json's 10 ms filtered
peak and contact duration.

A raw penalty force that chatters is chaotic: its samples, and what is read
from few of them (a 10 ms peak, the last sample with a positive force), move
by far more than the perturbation; what is averaged over 50 ms should not.
A test or a comparison of two builds (other threads, other sums, MPI) may
only ask of a measure what its range here allows.

usage: python3 scripts/round_off_sensitivity.py PROGRAM FILE.prm
           [--runs 6] [--relative 1e-12] [--work DIR]
The scene must have a Body 1 with an Initial velocity and History
interval = 1; VTU output is switched off."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "scripts"))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from contact_measures import measures  # noqa: E402
from testing import edit_prm, read_prm  # noqa: E402

COLUMNS = [("filtered peak (10 ms) [N/m]", "filtered_peak"),
           ("force trend peak (50 ms) [N/m]", "force_trend_peak_N_per_m"),
           ("force chatter [%]", "force_chatter_percent"),
           ("energy error [%]", "energy_error_percent"),
           ("contact duration [s]", "contact_duration_s")]


def initial_velocity(prm):
    """Body 1's Initial velocity in FILE.prm, as a list of floats."""
    value = read_prm(prm).get("Body 1/Initial velocity")
    if value is None:
        sys.exit(f"{prm}: no 'set Initial velocity' in subsection Body 1")
    return [float(v) for v in value.split(",")]


def run(program, prm, work, k, relative):
    velocity = [v * (1 + k * relative) for v in initial_velocity(prm)]
    name = os.path.join(work, f"run_{k}")
    edit_prm(prm, name + ".prm",
             {"Body 1/Initial velocity": ", ".join(repr(v) for v in velocity),
              "Output/Directory": name, "Output/VTU interval": 0})
    result = subprocess.run([program, name + ".prm"], cwd=work,
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"run {k} of {prm} failed (exit {result.returncode}):\n"
                 + result.stderr.strip())
    m = measures(name)
    with open(os.path.join(name, "summary.json")) as f:
        m["filtered_peak"] = json.load(f)["filtered_peak_contact_force_N_per_m"]
    return m


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("program")
    parser.add_argument("prm")
    parser.add_argument("--runs", type=int, default=6)
    parser.add_argument("--relative", type=float, default=1e-12)
    parser.add_argument("--work", default=None)
    args = parser.parse_args()
    program = os.path.abspath(args.program)
    prm = os.path.abspath(args.prm)
    for path in (program, prm):
        if not os.path.isfile(path):
            sys.exit(f"round_off_sensitivity: no file {path}")
    if args.runs < 2:
        sys.exit(f"round_off_sensitivity: --runs {args.runs}: at least 2 runs "
                 "are needed for a range")
    with tempfile.TemporaryDirectory() as scratch:
        work = os.path.abspath(args.work) if args.work else scratch
        os.makedirs(work, exist_ok=True)
        print(f"{os.path.relpath(prm, root)}: initial velocity of body 1 "
              f"scaled by 1 + k * {args.relative:g}")
        print("| k | " + " | ".join(c for c, _ in COLUMNS) + " |")
        print("|---" * (len(COLUMNS) + 1) + "|")
        rows = []
        for k in range(args.runs):
            m = run(program, prm, work, k, args.relative)
            rows.append(m)
            print(f"| {k} | " + " | ".join(f"{m[key]:.4g}" for _, key in COLUMNS)
                  + " |", flush=True)
        print("| range | " + " | ".join(
            f"{min(r[key] for r in rows):.4g} - {max(r[key] for r in rows):.4g}"
            for _, key in COLUMNS) + " |")


if __name__ == "__main__":
    main()
