#!/usr/bin/env python3
"""Step cost from 1e4 to 1e6 unknowns (issue 12): FEA Q9 levels 4-7 and IGA
p2 levels 5-8 of the Hertz benchmark (prm/hertz_fea_hrz.prm,
prm/hertz_iga_hrz.prm), HRZ and consistent mass, each run by
build/benchmarks/benchmark_step_cost (contact on: the cylinders touch from
t = 0 and the rounds stay inside the impact). The step is dt = 2.5e-4 s at
level 4, halved per level (stable for both masses). Prints one table:
ns per unknown per step, the bare stiffness mat-vec of the same matrices in
the same run, their ratio (of the fastest rounds, and the median of the
step/mat-vec pairs timed back to back, which a change of the machine's load
moves least), the contact's evaluation timed alone after a mat-vec (ms;
benchmark_step_cost's "contact alone"), the consistent step against the HRZ step (both normalised by
their run's mat-vec, by the paired ratios, so that a change of the load
between the runs cancels; raw; and both scenes in one process, their steps
timed alternately, the median of the pairs' ratios, by
build/benchmarks/benchmark_mass_step_ratio), peak memory and the Cholesky factors per
unknown, and the factorisation's set-up time.
usage: python3 benchmarks/step_cost_sweep.py [--quick] [--build build]
           [--only "METHOD:LEVEL" ...] [--repeats R]
  --quick: the two smallest levels of each method only.
  --only "IGA p2:8": that method and level only (may be repeated).
  --repeats R: each level's HRZ and consistent runs R times in turn (one
    table row per run); after the table, the medians of the R normalised
    and one-process consistent / HRZ ratios per level, since one run can
    fall into a slow phase of the machine."""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from testing import edit_prm  # noqa: E402

# File, levels, unknowns at level 4 (about 4 times more per level).
CASES = {"FEA Q9": ("prm/hertz_fea_hrz.prm", [4, 5, 6, 7], 16772),
         "IGA p2": ("prm/hertz_iga_hrz.prm", [5, 6, 7, 8], 4832)}
MASSES = ["HRZ", "consistent"]


def run(binary, *arguments):
    out = subprocess.run([binary, *map(str, arguments)], check=True,
                         capture_output=True, text=True).stdout
    line = [l for l in out.splitlines() if l.startswith("RESULT ")][-1]
    return {k: v for k, v in (item.split("=") for item in line.split()[1:])}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--only", action="append", default=[],
                        metavar="METHOD:LEVEL")
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error(f"--repeats {args.repeats}: at least 1 is allowed")
    selected = set()
    for item in args.only:
        method, _, level = item.rpartition(":")
        if method not in CASES or not level.isdigit() \
                or int(level) not in CASES[method][1]:
            parser.error(f"--only {item!r}: allowed are " + ", ".join(
                f"'{m}:{l}'" for m, (_, ls, _) in CASES.items() for l in ls))
        selected.add((method, int(level)))
    normalised_runs, one_process_runs = {}, {}
    binary = os.path.join(args.build, "benchmarks", "benchmark_step_cost")
    pair_binary = os.path.join(args.build, "benchmarks",
                               "benchmark_mass_step_ratio")
    rounds = 3
    header = ("| method | level | unknowns | mass | step [ns/unknown] "
              "| mat-vec [ns/unknown] | step / mat-vec | step / mat-vec "
              "(paired median) | contact alone [ms] | consistent / HRZ "
              "(normalised) | consistent / HRZ (raw) | consistent / HRZ "
              "(one process, paired) | peak memory "
              "[bytes/unknown] | factors [bytes/unknown] | factors "
              "[nonzeros/unknown] | factorisation [s] |")
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    with tempfile.TemporaryDirectory() as work:
        for method, (prm, levels, level_4_unknowns) in CASES.items():
            for level, repeat in ((l, k) for l in (levels[:2] if args.quick
                                                   else levels)
                                  for k in range(args.repeats)):
                if selected and (method, level) not in selected:
                    continue
                dt = 2.5e-4 / 2 ** (level - 4)
                # About 2e7 unknown-steps per round, at most 0.6 s of
                # simulated time in all rounds (inside the impact; a round
                # takes 1.25 steps per step timed: the benchmark's output
                # steps), at least 10 steps per round.
                unknowns = level_4_unknowns * 4 ** (level - 4)
                steps = max(10, min(int(0.6 / (1.25 * rounds * dt)),
                                    int(2e7 / unknowns)))
                results = {}
                names = {mass: os.path.join(work, f"{level}_{mass}.prm")
                         for mass in MASSES}
                for mass in MASSES:
                    edit_prm(os.path.join(root, prm), names[mass], {
                        "Discretization/Global refinements": level,
                        "Mass matrix/Scheme": mass,
                        "Time integration/Time step": dt,
                        "Time integration/Allow time step above the stable "
                        "estimate": "true",
                        "Output/VTU interval": 0,
                        "Output/Pressure profile times": "",
                        "Output/Directory": os.path.join(work, "out")})
                    results[mass] = run(binary, names[mass], steps, rounds)
                # Both scenes in one process, their steps alternately.
                pair = run(pair_binary, names["HRZ"], names["consistent"],
                           steps, rounds)
                assert pair["contact"] == "1", f"no contact in {method} {level}"
                one_process = float(pair["paired_ratio"])
                lumped = results["HRZ"]
                for mass in MASSES:
                    r = results[mass]
                    step, matvec = float(r["step_ns"]), float(r["matvec_ns"])
                    assert r["contact"] == "1", f"no contact in {method} {level}"
                    ratio = step / matvec
                    paired = float(r["paired_ratio"])
                    normalised = paired / float(lumped["paired_ratio"])
                    raw = step / float(lumped["step_ns"])
                    consistent = mass == "consistent"
                    if consistent:
                        normalised_runs.setdefault((method, level),
                                                   []).append(normalised)
                        one_process_runs.setdefault((method, level),
                                                    []).append(one_process)
                    contact = float(r["contact_us"]) / 1e3
                    print(f"| {method} | {level} | {r['unknowns']} | {mass} "
                          f"| {step:.1f} | {matvec:.1f} | {ratio:.2f} "
                          f"| {paired:.2f} | {contact:.3f} "
                          f"| {normalised:.2f} | {raw:.2f} "
                          f"| {one_process:.2f} "
                          if consistent else
                          f"| {method} | {level} | {r['unknowns']} | {mass} "
                          f"| {step:.1f} | {matvec:.1f} | {ratio:.2f} "
                          f"| {paired:.2f} | {contact:.3f} | - | - | - ",
                          end="")
                    print(f"| {float(r['peak_bytes']):.0f} "
                          + (f"| {float(r['factor_bytes']):.0f} "
                             f"| {float(r['factor_nnz']):.1f} "
                             f"| {float(r['factor_setup_s']):.2f} |"
                             if consistent else "| - | - | - |"), flush=True)
    if args.repeats > 1:
        print()
        for label, measured in (("normalised", normalised_runs),
                                ("one process, paired", one_process_runs)):
            for (method, level), runs in measured.items():
                print(f"{method} level {level}: consistent / HRZ ({label}), "
                      f"median of {len(runs)} runs "
                      f"{statistics.median(runs):.2f} (runs: "
                      + ", ".join(f"{r:.2f}" for r in runs) + ")")


if __name__ == "__main__":
    main()
