#!/usr/bin/env python3
"""Which tasks took the cores while a command ran: the kernel's sched_switch
events (tracefs, trace_clock mono) over the command, summed per task.

Prints each task's time on the cores, the part of it that preempted one of
the program's threads (a switch away from a runnable program thread), the
cores' idle time, and the runs of other tasks longer than 1 ms. With
--steps (the run's step_times.csv, Output/Step times = true, whose clock is
the same monotonic clock) also the steps whose time outside the passes
exceeds the run's median by more than 1 ms (the stalls of
alternating_runs.py), and how many of them had another task on a core for
at least half the stall.

Needs root (it mounts tracefs at /sys/kernel/tracing if it is not there);
the trace is cleared, its events switched off and its clock and buffer
size restored afterwards. The
command's output goes to stderr, the report to stdout.

usage: python3 benchmarks/scheduler_trace.py [--program isoimpact]
          [--steps out/step_times.csv] [--keep FILE] -- COMMAND [ARGUMENTS]
  e.g. -- mpirun --allow-run-as-root -np 2 -x DEAL_II_NUM_THREADS=1
          build/isoimpact FILE.prm, or -- sleep 10 while a run goes on.
"""
import argparse
import collections
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from alternating_runs import stalls, step_times, wrapped_command  # noqa: E402

TRACING = "/sys/kernel/tracing"
EVENTS = ["sched_switch"]
LINE = re.compile(r"^\s*(?P<task>.+?)-(?P<pid>\d+)\s+\[(?P<cpu>\d+)\]\s+\S+\s+"
                  r"(?P<time>[\d.]+): (?P<event>\w+): (?P<rest>.*)$")
SWITCH = re.compile(r"prev_comm=(?P<prev>.*?) prev_pid=\d+ prev_prio=\d+ "
                    r"prev_state=(?P<state>\S+) ==> next_comm=(?P<next>.*?) next_pid=\d+")


def write(name, value):
    with open(os.path.join(TRACING, name), "w") as f:
        f.write(value)


def record(command):
    """Runs `command` with the scheduler's events traced; its exit code and
    the trace's text."""
    if not os.path.exists(os.path.join(TRACING, "trace")):
        subprocess.run(["mount", "-t", "tracefs", "nodev", TRACING], check=True)
    write("tracing_on", "0")
    with open(os.path.join(TRACING, "trace_clock")) as f:
        clock = re.search(r"\[(\w+)\]", f.read())[1]
    with open(os.path.join(TRACING, "buffer_size_kb")) as f:
        size = f.read().split()[0]
    write("trace_clock", "mono")
    write("buffer_size_kb", "16384")
    write("trace", "")
    for event in EVENTS:
        write(f"events/sched/{event}/enable", "1")
    try:
        write("tracing_on", "1")
        # (the command's output on stderr: stdout is the report's)
        code = subprocess.run(command, stdout=sys.stderr).returncode
        write("tracing_on", "0")
        with open(os.path.join(TRACING, "trace")) as f:
            text = f.read()
    finally:
        write("tracing_on", "0")
        for event in EVENTS:
            write(f"events/sched/{event}/enable", "0")
        write("trace", "")
        write("trace_clock", clock)
        write("buffer_size_kb", size)
    return code, text


def intervals(text):
    """(cpu, task, begin, end, preempting) per stretch a task held a core;
    preempting: the task before it was one of the program's, runnable."""
    current, result = {}, []
    for line in text.splitlines():
        match = LINE.match(line)
        if not match or match["event"] != "sched_switch":
            continue
        switch = SWITCH.search(match["rest"])
        if not switch:
            continue
        cpu, time = int(match["cpu"]), float(match["time"])
        if cpu in current:
            task, begin, preempting = current[cpu]
            result.append((cpu, task, begin, time, preempting))
        current[cpu] = (switch["next"], time,
                        (switch["prev"], switch["state"].startswith("R")))
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--program", default="isoimpact",
                        help="the program's task name (its threads' too)")
    parser.add_argument("--steps", help="the run's step_times.csv, read after it")
    parser.add_argument("--keep", help="a file for the raw trace")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = wrapped_command(parser, args.command)
    if os.geteuid() != 0:
        sys.exit("scheduler_trace.py needs root (tracefs)")
    code, text = record(command)
    if args.keep:
        with open(args.keep, "w") as f:
            f.write(text)
    stretches = intervals(text)
    if not stretches:
        sys.exit("no sched_switch events in the trace")
    begin = min(s[2] for s in stretches)
    end = max(s[3] for s in stretches)
    if args.steps:
        if not os.path.exists(args.steps):
            sys.exit(f"--steps {args.steps}: no such file after the command "
                     f"(exit code {code}); Output/Step times = true writes it")
        rows = step_times(args.steps)
        begin, end = rows[0][2], rows[-1][2]

    def program(task):
        return task.startswith(args.program)

    def name(task):  # threads of one kind under one name
        return re.sub(r"[/:-]?\d+$", "", task)

    on_core, preempting = collections.defaultdict(float), collections.defaultdict(float)
    long_runs = collections.Counter()
    idle = 0.
    for cpu, task, a, b, (before, runnable) in stretches:
        a, b = max(a, begin), min(b, end)
        if b <= a:
            continue
        if task.startswith("swapper"):
            idle += b - a
            continue
        on_core[name(task)] += b - a
        if not program(task):
            if program(before) and runnable:
                preempting[name(task)] += b - a
            if b - a > 1e-3:
                long_runs[name(task)] += 1
    span = end - begin
    print(f"{span:.3f} s traced ({'the steps of ' + args.steps if args.steps else 'the command'}), "
          f"exit code {code}")
    print("task: time on the cores [ms] (of it preempting the program's threads); "
          "runs over 1 ms")
    for task, seconds in sorted(on_core.items(), key=lambda x: -x[1])[:12]:
        print(f"  {task}: {1e3 * seconds:.1f} ({1e3 * preempting[task]:.1f}); "
              f"{long_runs[task]}")
    print(f"  idle, all cores: {1e3 * idle:.1f}")
    if args.steps:
        middle, stalled = stalls([(b[2] - a[2]) - b[3] for a, b in zip(rows, rows[1:])])
        by_task, explained = collections.Counter(), 0
        for k, extra in stalled:
            a, b = rows[k][2], rows[k + 1][2]
            during = collections.defaultdict(float)
            for cpu, task, s, e, _ in stretches:
                overlap = min(e, b) - max(s, a)
                if overlap > 0 and not program(task) and not task.startswith("swapper"):
                    during[name(task)] += overlap
            if during and max(during.values()) >= 0.5 * extra:
                explained += 1
                by_task[max(during, key=during.get)] += 1
        print(f"steps {len(rows) - 1}, median time outside the passes {1e3 * middle:.3f} ms, "
              f"stalls {len(stalled)}; with another task on a core for at least half the "
              f"stall: {explained} ({', '.join(f'{t} {n}' for t, n in by_task.most_common())})")
    sys.exit(code)


if __name__ == "__main__":
    main()
