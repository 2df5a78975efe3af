"""summary.json's wall_time_parts_s: the set-up, the time loop (the initial
acceleration and the steps) and the output (files, history with the
energies) are positive and add up to the total (the whole run but the reading of the parameters and
the writing of summary.json) within 5 %; the initial acceleration
(initial_acceleration_s) is a positive part of the time loop, and so is the
time in the bodies' passes (passes_s_per_rank, one process: one entry),
which the initial acceleration is not part of; the time loop
and output of the run together are wall_time_s within 5 %.

usage: summary_wall_time.py OUTPUT_DIR (the fixture run's)"""
import json
import os
import sys

from testing import check_close, check_true, report

summary = json.load(open(os.path.join(sys.argv[1], "summary.json")))
parts = summary["wall_time_parts_s"]
check_true("wall_time_parts_s has setup, time_loop, output, total",
           list(parts) == ["setup", "time_loop", "output", "total"])
for key, value in parts.items():
    check_true(f"{key} = {value:.4g} s > 0", value > 0.)
print(f"     time loop {100 * parts['time_loop'] / parts['total']:.1f} %, output "
      f"{100 * parts['output'] / parts['total']:.1f} %, set-up {100 * parts['setup'] / parts['total']:.1f} %")
check_close("setup + time_loop + output [s] against total", parts["setup"] + parts["time_loop"] + parts["output"],
            parts["total"], 0.05)
initial = summary["initial_acceleration_s"]
check_true(f"initial_acceleration_s = {initial:.4g} s in (0, time_loop]",
           0. < initial <= parts["time_loop"])
passes = summary["passes_s_per_rank"]
check_true(f"passes_s_per_rank = {passes} has one entry per rank ({summary['mpi_ranks']})",
           len(passes) == summary["mpi_ranks"])
for p in passes:
    check_true(f"passes {p:.4g} s in (0, time_loop - initial_acceleration_s = "
               f"{parts['time_loop'] - initial:.4g} s]",
               0. < p <= parts["time_loop"] - initial)
check_close("time_loop + output [s] against wall_time_s", parts["time_loop"] + parts["output"],
            summary["wall_time_s"], 0.05)
report()
