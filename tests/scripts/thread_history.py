"""The program on one thread against two threads: the same history, to the
last bit. On one process the bodies' steps run side by side as parallel
tasks (central_difference.cc), the lumped pass and the energies are summed
in blocks of a fixed size, and the consistent mass's factor is split into
the same subtrees whatever the threads (mass_solver.cc): so every column of
history.csv and the energy error of summary.json must not differ at all.
A data race between the bodies' tasks, or a sum whose order follows the
threads, would show here. With Parallel/Thread partition = by body each
body's pass is one task: the same bits again.

Usage: thread_history.py PROGRAM WORKDIR CASE [CASE ...], a CASE being a
parameter file, optionally followed by edits:
FILE.prm[@Section/Key=value[@...]] (History interval = 1 is set)."""
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np

from testing import check_close, check_true, edit_prm, report

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "scripts"))
import isoimpact_results  # noqa: E402

program, workdir = sys.argv[1], sys.argv[2]
os.makedirs(workdir, exist_ok=True)


def run(prm, edits, name, threads):
    out = os.path.join(workdir, name)
    shutil.rmtree(out, ignore_errors=True)
    edited = edit_prm(prm, os.path.join(workdir, name + ".prm"),
                      {**edits, "Output/Directory": name, "Output/History interval": "1"})
    result = subprocess.run([program, edited], cwd=workdir, capture_output=True, text=True,
                            env={**os.environ, "DEAL_II_NUM_THREADS": str(threads)})
    print(f"--- {program} {edited} ({threads} threads): exit {result.returncode}\n"
          f"{result.stdout[-800:]}{result.stderr[-1500:]}")
    check_true(f"{name}: exit 0", result.returncode == 0)
    return (isoimpact_results.read_history(out),
            json.load(open(os.path.join(out, "summary.json"))))


for case in sys.argv[3:]:
    prm, *changes = case.split("@")
    edits = dict(change.split("=", 1) for change in changes)
    label = os.path.splitext(os.path.basename(prm))[0] + "".join(
        "_" + re.sub(r"[^A-Za-z0-9]+", "_", change) for change in changes)
    one, one_summary = run(prm, edits, label + "_1_thread", 1)
    two, two_summary = run(prm, edits, label + "_2_threads", 2)
    check_true(f"{label}: both histories have the same columns and rows (> 100)",
               one.keys() == two.keys() and len(one["time"]) == len(two["time"]) > 100)
    for column in one:
        check_close(f"{label}: max |difference| of {column} over the whole run",
                    np.max(np.abs(one[column] - two[column])), 0., 0., relative=False)
    check_close(f"{label}: max energy error, 2 threads against 1",
                two_summary["max_energy_error"], one_summary["max_energy_error"], 0.)
    partition = edits.get("Parallel/Thread partition", "dynamic")
    check_true(f"{label}: summary.json gives thread_partition = {partition}",
               two_summary.get("thread_partition") == partition)
report()
