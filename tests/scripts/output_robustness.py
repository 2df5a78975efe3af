"""Output that survives a stop, a full disk and a rerun (issue 10):
- a rerun into a folder with an earlier run's files removes the files the
  program owns (and only those) before writing;
- an end time that is not a multiple of the step: the last step lands on it;
- SIGTERM and SIGKILL during a run leave history.csv with complete rows only,
  summary.json absent or valid JSON and solution.pvd naming existing files;
- a write that fails (a file size limit, RLIMIT_FSIZE, which fails writes as
  a full disk does; and a 64 kB tmpfs when it can be mounted) stops the run
  with exit 1 and a message naming the file, and leaves no half-written file."""
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

from testing import check_close, check_true, edit_prm, report

program, good_prm, workdir = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(workdir, ignore_errors=True)
os.makedirs(workdir)


def prm(name, edits):
    return edit_prm(good_prm, os.path.join(workdir, name + ".prm"),
                    {"Output/Directory": name, **edits})


def history_rows(folder):
    """The data rows of history.csv; checks that every line is complete."""
    text = open(os.path.join(folder, "history.csv")).read()
    lines = text.split("\n")
    check_true(f"{folder}: history.csv ends with a complete line", text.endswith("\n"))
    header = [line for line in lines if line.startswith("time,")]
    check_true(f"{folder}: history.csv has its header", len(header) == 1)
    n = len(header[0].split(",")) if header else 0
    rows = [line.split(",") for line in lines if line and line[0].isdigit()]
    complete = all(len(row) == n and all(float(x) == float(x) for x in row) for row in rows)
    check_true(f"{folder}: all {len(rows)} rows have the {n} numbers of the header", complete)
    return rows


def check_files_readable(folder, max_tmp=0):
    """summary.json, solution.pvd, every .vtu/.pvtu readable; at most max_tmp
    .tmp files (a file being written when a signal stops the run)."""
    summary = os.path.join(folder, "summary.json")
    if os.path.exists(summary):
        try:
            json.load(open(summary))
            valid = True
        except ValueError:
            valid = False
        check_true(f"{folder}: summary.json is valid JSON", valid)
    else:
        check_true(f"{folder}: summary.json absent", True)
    pvd = os.path.join(folder, "solution.pvd")
    if os.path.exists(pvd):
        names = [d.get("file") for d in ElementTree.parse(pvd).iter("DataSet")]
        check_true(f"{folder}: solution.pvd parses and its {len(names)} files exist",
                   all(os.path.exists(os.path.join(folder, n)) for n in names))
    for name in os.listdir(folder):
        if name.endswith(".vtu") or name.endswith(".pvtu"):
            ElementTree.parse(os.path.join(folder, name))  # raises if cut
    check_true(f"{folder}: every .vtu/.pvtu parses as XML", True)
    n_tmp = sum(n.endswith(".tmp") for n in os.listdir(folder))
    check_true(f"{folder}: {n_tmp} .tmp files (at most {max_tmp})", n_tmp <= max_tmp)


# 1. A rerun into a folder holding an earlier run's files.
folder = os.path.join(workdir, "rerun")
os.makedirs(folder)
stale = ["body1_0099.vtu", "body2_0099.vtu", "solution_0099.pvtu", "contact_pressure_t9.9990.csv",
         "summary.json.tmp", "body1_0100.vtu.tmp", "pass_times.csv", "step_times.csv"]
for name in stale + ["notes.txt"]:
    open(os.path.join(folder, name), "w").write("an earlier run\n")
open(os.path.join(folder, "summary.json"), "w").write('{"steps": 99999}\n')
run = subprocess.run([program, prm("rerun", {"Time integration/End time": "0.05",
                                             "Output/VTU interval": "50"})],
                     cwd=workdir, capture_output=True, text=True)
check_true("rerun: exit 0", run.returncode == 0)
check_true("rerun: says it removed the 9 files of the earlier run",
           "removed 9 files of an earlier run" in run.stdout)
left = os.listdir(folder)
check_true("rerun: no stale file left", not any(name in left for name in stale))
check_true("rerun: a file the program does not own is kept", "notes.txt" in left)
check_close("rerun: summary.json is the new run's (steps)",
            json.load(open(os.path.join(folder, "summary.json")))["steps"], 100, 0)
check_true("rerun: the new VTU files", "body1_0002.vtu" in left and "body1_0003.vtu" not in left)

# 2. An end time that is not a multiple of the step: 201 steps of 0.10025/201 s.
run = subprocess.run([program, prm("end_time", {"Time integration/End time": "0.10025",
                                                "Output/VTU interval": "0",
                                                "Output/Step times": "true"})],
                     cwd=workdir, capture_output=True, text=True)
check_true("end time 0.10025 s, step 5e-4 s: exit 0", run.returncode == 0)
summary = json.load(open(os.path.join(workdir, "end_time", "summary.json")))
check_close("end time: steps", summary["steps"], 201, 0)
check_close("end time: step shortened to End time / 201 [s]", summary["time_step_s"], 0.10025 / 201, 1e-14)
rows = history_rows(os.path.join(workdir, "end_time"))
check_close("end time: the last row is at the end time [s]", float(rows[-1][0]), 0.10025, 1e-12)
# Output/Step times: each step's end on the monotonic clock (step 0: the
# loop's start, after the initial acceleration), within the time loop's and
# the output's wall time.
lines = open(os.path.join(workdir, "end_time", "step_times.csv")).read().split("\n")
check_true("step_times.csv: its header", lines[0] == "step,time_s,monotonic_clock_s,passes_s")
table = [[float(x) for x in line.split(",")] for line in lines[1:] if line]
check_close("step_times.csv: a row per step and one for step 0", len(table), 202, 0)
check_true("step_times.csv: steps 0, 1, ..., 201",
           [row[0] for row in table] == list(range(202)))
check_close("step_times.csv: time of the last row = end time [s]", table[-1][1], 0.10025, 1e-12)
check_true("step_times.csv: the clock grows from step to step",
           all(b[2] > a[2] for a, b in zip(table, table[1:])))
wall = summary["wall_time_parts_s"]
span = table[-1][2] - table[0][2]
print(f"step_times.csv: steps 1-201 span {span:.4f} s; time loop less the initial "
      f"acceleration {wall['time_loop'] - summary['initial_acceleration_s']:.4f} s, "
      f"time loop and output {wall['time_loop'] + wall['output']:.4f} s")
check_true("step_times.csv: steps 1-201 span at least the time loop less the initial "
           "acceleration and at most the time loop and the output",
           wall["time_loop"] - summary["initial_acceleration_s"] <= span
           <= wall["time_loop"] + wall["output"])
passes = sum(row[3] for row in table)
print(f"step_times.csv: passes {passes:.6f} s, summary.json {summary['passes_s_per_rank'][0]:.6f} s")
check_close("step_times.csv: the steps' passes add up to summary.json's passes_s_per_rank",
            passes, summary["passes_s_per_rank"][0], 1e-9)
check_true("step_times.csv: each step's passes within the step",
           all(0 < b[3] <= b[2] - a[2] for a, b in zip(table, table[1:])))
check_true("end time: the setup says the step was shortened",
           "the step 0.0005 s shortened so that the last step ends at the end time" in run.stdout)
# The run stops inside the impact: no contact duration to report as one.
check_true("end time inside the impact: contact_ended is false",
           summary["contact_ended"] is False)
# The cylinders touch at t = 0; the first step (t = dt) has the first
# active contact point.
check_close("end time inside the impact: contact time so far [s] = end time - dt",
            summary["contact_duration_s"], 0.10025 - summary["time_step_s"], 1e-12)
check_true("end time inside the impact: no relative error of the duration (null)",
           summary["relative_error"]["contact_duration"] is None)
check_true("end time inside the impact: the program warns that the contact lasts",
           "still in contact at the end time" in run.stdout)

# 3. SIGTERM and SIGKILL during a run (tens of seconds of steps, a progress line
# every 1 %).
for name, sig in (("sigterm", signal.SIGTERM), ("sigkill", signal.SIGKILL)):
    process = subprocess.Popen([program, prm(name, {"Time integration/End time": "50",
                                                   "Output/VTU interval": "400",
                                                   "Output/Progress interval": "1"})],
                               cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    time.sleep(1.5)
    process.send_signal(sig)
    process.communicate()
    folder = os.path.join(workdir, name)
    check_true(f"{name}: the run was stopped by the signal (exit {process.returncode})",
               process.returncode == -sig)
    if os.path.exists(folder):
        rows = history_rows(folder)
        check_files_readable(folder, max_tmp=1)
        print(f"{name}: {len(rows)} rows when stopped")
    else:
        check_true(f"{name}: stopped before the output folder was created", True)


# 4. A write that fails: every file is limited to 50 kB (the history needs
# about 180 kB), the signal SIGXFSZ ignored so that the write returns EFBIG.
def limit_files(size):
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
    return limit


run = subprocess.run([program, prm("file_limit", {"Output/VTU interval": "0",
                                                 "Output/Progress interval": "1"})],
                     cwd=workdir, capture_output=True, text=True, preexec_fn=limit_files(50000))
print(run.stderr)
check_true("history beyond the file limit: exit 1", run.returncode == 1)
check_true("history beyond the file limit: message names history.csv and the error",
           "writing 'file_limit/history.csv' failed: File too large" in run.stderr)
folder = os.path.join(workdir, "file_limit")
rows = history_rows(folder)
check_true(f"history beyond the file limit: {len(rows)} complete rows kept", len(rows) > 100)
check_true("history beyond the file limit: history.csv within the 50 kB",
           os.path.getsize(os.path.join(folder, "history.csv")) <= 50000)
check_true("history beyond the file limit: no summary.json", not os.path.exists(
    os.path.join(folder, "summary.json")))

run = subprocess.run([program, prm("vtu_limit", {"Output/VTU interval": "100"})],
                     cwd=workdir, capture_output=True, text=True, preexec_fn=limit_files(100000))
print(run.stderr)
check_true("VTU beyond the file limit: exit 1", run.returncode == 1)
check_true("VTU beyond the file limit: message names the .vtu file",
           "writing 'vtu_limit/body1_0001.vtu' failed: File too large" in run.stderr)
check_files_readable(os.path.join(workdir, "vtu_limit"))

# A full disk, where a tmpfs can be mounted (as root).
tiny = os.path.join(workdir, "tiny")
os.makedirs(tiny)
if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", tiny],
                  capture_output=True).returncode == 0:
    try:
        run = subprocess.run([program, prm("tiny/out", {"Output/VTU interval": "0"})],
                             cwd=workdir, capture_output=True, text=True)
        print(run.stderr)
        check_true("full 64 kB tmpfs: exit 1", run.returncode == 1)
        check_true("full 64 kB tmpfs: 'No space left on device' named",
                   "No space left on device" in run.stderr and "failed" in run.stderr)
        history_rows(os.path.join(tiny, "out"))
        check_files_readable(os.path.join(tiny, "out"))
    finally:
        subprocess.run(["umount", tiny])
else:
    print("(no tmpfs: the full-disk case is covered by the file size limit above)")
report()
