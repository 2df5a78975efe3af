#!/usr/bin/env python3
"""When a core was taken from the program: `perf record -a` samples every
core at a fixed rate on the monotonic clock (cpu-clock, 4000 Hz: one sample
each 0.25 ms whatever runs, the idle task included). Two things take a core:
- another task of this machine (a sample of a task that is neither the
  program nor the idle task): the kernel's threads (kdamond), the sandbox's
  agents, mpirun;
- the host: a virtual CPU that is not running takes no samples, so a gap
  between two samples of one core longer than --gap (0.75 ms, three
  periods) is time the core was away from this machine (or had its
  interrupts off that long), whichever task was current.
With --steps (the run's step_times.csv, Output/Step times = true, the same
clock) each step is quiet if neither touched it nor the step before it
(the ranks need not meet at every step, so a core taken in one step may
delay the next); the report gives the mean step and passes over all steps
and over the quiet ones, and which of the stalls (alternating_runs.py: rest
more than 1 ms over the run's median) and of the slow steps (more than 1
ms longer than the median of the 50 steps around them) had another task,
an absent core, both or neither.

Needs perf (Debian: linux-perf) and root or kernel.perf_event_paranoid <= 0
for -a. The command's output goes to stderr, the report to stdout.

usage: python3 benchmarks/cpu_samples.py [--steps out/step_times.csv]
          [--program isoimpact] [--keep FILE] -- COMMAND [ARGUMENTS]
"""
import argparse
import bisect
import collections
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from alternating_runs import slow_steps, stalls, step_times, wrapped_command  # noqa: E402

RATE = 4000  # samples per second and core
GAP = 0.75e-3  # [s]: longer than three sampling periods
IDLE = "swapper"
SAMPLE = re.compile(r"^\s*(?P<task>.+?)\s+(?P<tid>\d+)\s+\[(?P<cpu>\d+)\]\s+(?P<time>[\d.]+):")


def start(path, command=None):
    """perf record of every core into `path`, of `command` or until stop()."""
    if shutil.which("perf") is None:
        sys.exit("cpu_samples.py: no perf on this machine (Debian: apt-get install linux-perf)")
    return subprocess.Popen(["perf", "record", "-q", "-e", "cpu-clock", "-F", str(RATE),
                             "-a", "-k", "CLOCK_MONOTONIC", "-o", path]
                            + (["--"] + command if command else []),
                            stdout=sys.stderr, stderr=sys.stderr)


def stop(recorder):
    recorder.send_signal(signal.SIGINT)
    recorder.wait()


def load(path):
    """Each core's samples (time [s], task), in time order."""
    text = subprocess.run(["perf", "script", "-i", path, "-F", "comm,tid,cpu,time"],
                          capture_output=True, text=True, check=True).stdout
    cores = collections.defaultdict(list)
    for line in text.splitlines():
        match = SAMPLE.match(line)
        if match:
            cores[int(match["cpu"])].append((float(match["time"]), match["task"]))
    for samples in cores.values():
        samples.sort()
    return cores


def disturbances(cores, program, gap=GAP):
    """The stretches (begin, end, core, what) in which a core was not the
    program's: 'absent' (no sample for longer than `gap`) or the other
    task's name (one sampling period before each of its samples)."""
    taken = []
    for core, samples in cores.items():
        for (t0, _), (t1, task) in zip(samples, samples[1:]):
            if t1 - t0 > gap:
                taken.append((t0, t1, core, "absent"))
            elif task not in (program, IDLE):
                taken.append((max(t0, t1 - 1.0 / RATE), t1, core, task))
    taken.sort()
    return taken


class Overlaps:
    """Which stretches of `taken` overlap a span of time."""

    def __init__(self, taken):
        self.taken = taken
        self.begins = [t[0] for t in taken]
        self.longest = max((t[1] - t[0] for t in taken), default=0.0)

    def __call__(self, begin, end):
        first = bisect.bisect_left(self.begins, begin - self.longest)
        last = bisect.bisect_right(self.begins, end)
        return [t for t in self.taken[first:last] if t[1] > begin and t[0] < end]


def taken_per_core(overlaps, spans, n_cores):
    """The share of time [s per s and core] the cores were away and with
    other tasks over `spans` (begin, end)."""
    away = other = 0.0
    for begin, end in spans:
        for t in overlaps(begin, end):
            part = min(t[1], end) - max(t[0], begin)
            if t[3] == "absent":
                away += part
            else:
                other += part
    total = n_cores * sum(end - begin for begin, end in spans)
    return away / total, other / total


def quiet_steps(rows, overlaps):
    """For each step of step_times.csv's rows after the first (the loop's
    start): whether no core was taken in it nor in the step before it."""
    touched = [bool(overlaps(a[2], b[2])) for a, b in zip(rows, rows[1:])]
    return [not t and not (k > 0 and touched[k - 1]) for k, t in enumerate(touched)]


def report(cores, program, rows=None):
    if not cores:
        sys.exit("no samples")
    begin = max(s[0][0] for s in cores.values())
    end = min(s[-1][0] for s in cores.values())
    if rows:
        begin, end = max(begin, rows[1][2]), min(end, rows[-1][2])
    taken = [t for t in disturbances(cores, program) if t[0] >= begin and t[1] <= end]
    print(f"{end - begin:.2f} s sampled at {RATE} Hz per core"
          + (" (the steps after the first)" if rows else ""))
    for core in sorted(cores):
        absent = [t[1] - t[0] for t in taken if t[2] == core and t[3] == "absent"]
        others = collections.Counter()
        for t in taken:
            if t[2] == core and t[3] != "absent":
                others[t[3]] += t[1] - t[0]
        print(f"  core {core}: absent {1e3 * sum(absent):.0f} ms in {len(absent)} gaps"
              + (f" (longest {1e3 * max(absent):.1f} ms)" if absent else "")
              + "; other tasks " + (", ".join(f"{task} {1e3 * s:.0f} ms"
                                            for task, s in others.most_common(5)) or "none"))
    if not rows:
        return
    overlaps = Overlaps(taken)
    # The steps after the first (its caches); each: duration, passes, quiet.
    quiet = quiet_steps(rows[1:], overlaps)
    steps = [(b[2] - a[2], b[3], q) for a, b, q in zip(rows[1:], rows[2:], quiet)]
    for what, chosen in (("all", steps), ("quiet", [s for s in steps if s[2]])):
        if chosen:
            print(f"  {what} steps: {len(chosen)}, mean step "
                  f"{1e3 * statistics.mean(s[0] for s in chosen):.3f} ms, passes "
                  f"{1e3 * statistics.mean(s[1] for s in chosen):.3f} ms")
    for what, found_excess in (("stalls", stalls([s[0] - s[1] for s in steps])[1]),
                               ("slow steps", slow_steps([s[0] for s in steps]))):
        kinds = collections.Counter()
        for k, excess in found_excess:
            found = overlaps(rows[k + 1][2], rows[k + 2][2])
            absent = any(t[3] == "absent" for t in found)
            other = any(t[3] != "absent" for t in found)
            kinds[("another task" if other else "") + (" and " if other and absent else "")
                  + ("a core absent" if absent else "") or "neither"] += 1
        print(f"  {what}: " + (", ".join(f"{n} {kind}" for kind, n in kinds.most_common())
                               or "none")
              + (f" ({1e3 * sum(e for _, e in found_excess) / len(steps):.3f} ms per step"
                 f" in all, {sum(steps[k][2] for k, _ in found_excess)} of them"
                 " quiet)" if found_excess else ""))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", help="the run's step_times.csv (read after the command)")
    parser.add_argument("--program", default="isoimpact")
    parser.add_argument("--keep", help="keep perf's data in this file")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = wrapped_command(parser, args.command)
    path = args.keep or tempfile.mktemp(suffix=".perf.data")
    code = start(path, command).wait()
    rows = None
    if args.steps:
        if not os.path.exists(args.steps):
            if not args.keep:
                os.remove(path)
            sys.exit(f"--steps {args.steps}: no such file after the command (exit {code})")
        rows = step_times(args.steps)
    report(load(path), args.program, rows)
    if not args.keep:
        os.remove(path)
    sys.exit(code)


if __name__ == "__main__":
    main()
