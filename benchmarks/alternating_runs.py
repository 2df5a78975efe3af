#!/usr/bin/env python3
"""2 MPI ranks x 1 thread against 1 rank x 2 threads (issue 13) on one
machine whose cores change speed from minute to minute: both runs at once,
taking turns. Whole runs one after the other (benchmarks/mpi_step_cost.py)
see the machine at different times, and their ratio moved by 10-30 %
between rounds (doc/parallel.md, sessions 18, 46-49); here the runs are set
up one after the other, then held (SIGSTOP) and resumed (SIGCONT) in turn,
`--window` seconds each, so that each round's windows lie seconds apart.
Each run writes the end of every step on the monotonic clock
(`Output/Step times = true`, step_times.csv); a window's time per step is
the mean over the steps that began and ended inside it, its first step left
out (the caches after the other run). Round by round, the step of 2 ranks
over that of 2 threads (the windows' order alternates between rounds); the
table gives their median and its distribution-free interval (the sign
test's, as mpi_step_cost.py), and in how many rounds 2 ranks were no
slower. With --serial, also 1 rank x 1 thread, for the speed-up (its run
has half the steps). Two processes of one configuration kept speeds up to
12 % apart for a whole run (`--also "2 threads, again"`, doc/parallel.md,
session 50): one run decides nothing; the sign of the ratio over several
runs does.

The scene: the Hertz benchmark, prm/hertz_fea_hrz.prm at Global
refinements 7 or prm/hertz_iga_hrz.prm at 8 (about 1e6 unknowns), the time
step of mpi_step_cost.py (2.5e-4 s at level 4, halved per level), no
ParaView output, history every 100 steps.

usage: python3 benchmarks/alternating_runs.py [--method "FEA Q9"|"IGA p2"]
          [--level L] [--steps 6000] [--window 1.0] [--build build] [--serial]
          [--also "2 ranks, unbound" | "2 ranks, measured" | "2 ranks, claimed"
                  | "2 threads, by body" | "2 threads, again" | "2 ranks, again"]
          [--keep FOLDER]
          [--variant NAME=VARIABLE=VALUE] [--variant-unbound NAME=VARIABLE=VALUE]
          [--setup-order random|given]
          [--analyse FOLDER] [--against LABEL] [--sampled] [--frames]
  --steps: steps of each 2-core run; the turns go on until every run ended
    (a round counts where both 2-core runs had a window with steps).
  --also: a further run (repeatable), each against 2 threads as 2 ranks are:
    2 ranks with mpirun --bind-to none (Open MPI binds 2 ranks to a core
    each by default; the threads are not bound), with Load balancing =
    measured or claimed (the default for two bodies, automatic, is shared
    memory on one node), 2 threads with Thread partition = by body, 2
    threads or 2 ranks again in processes of their own (how far two runs of
    one configuration differ).
  --variant: a further 2-rank run whose ranks see VARIABLE=VALUE (mpirun
    -x; several separated by commas), labelled "2 ranks, NAME": for a
    switch of a throw-away build, e.g. the trace patch of benchmarks/traces/
    (--variant "wide band=ISOIMPACT_BAND=0.95"); --variant-unbound: the
    same with mpirun --bind-to none.
  --setup-order: random (default) or as given (2 threads, 2 ranks, the
    --also runs, 1 x 1): a run set up later was up to 12 % faster than the
    same configuration set up first.
  --keep: the runs' folder (windows.json, each run's step_times.csv), kept;
    --analyse FOLDER prints its table again.
  --against: the run the others are compared with, round by round
    (default 2 threads; e.g. --analyse FOLDER --against "2 ranks").
  --sampled: every core sampled during the turns (perf record -a into
    FOLDER/samples.data, benchmarks/cpu_samples.py); the table is given
    again over the quiet steps only: those in which, and in the step before
    which, no core was taken by another task of the machine or was away
    (a virtual CPU the host ran something else on). Needs perf and root.
  With both "2 threads, again" and "2 ranks, again", the table also pairs
    the mean of each configuration's two processes, round by round; so too
    for a variant run twice (--variant "NAME=..." --variant "NAME,
    again=..."), against the two processes of --against.
  --frames: once every run is set up, how physically contiguous each
    process's memory is (benchmarks/frame_contiguity.py; root), printed and
    kept in windows.json.
The table also counts each run's stalls: steps whose rest (outside the
passes) exceeds the run's median rest by more than 1 ms, and what they add
per step; and its slow steps: steps more than 1 ms longer than the median
of the 50 steps around them, and what they add per step. Only the latter
compare 2 ranks with 2 threads: a thread that waits for the other's last
block waits in the pass, a rank that waits for the other's pass in the
rest (doc/parallel.md, session 53)."""
import argparse
import json
import os
import random
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "benchmarks"))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from mpi_step_cost import CASES, median_interval, program_processes  # noqa: E402
from testing import edit_prm  # noqa: E402

# label: ranks, threads, mpirun's options, the scene's parameters.
CONFIGS = {"2 threads": (1, 2, [], {}), "2 ranks": (2, 1, [], {}), "1 x 1": (1, 1, [], {}),
           # --also: variants, each against 2 threads too.
           "2 ranks, unbound": (2, 1, ["--bind-to", "none"], {}),
           "2 ranks, measured": (2, 1, [], {"Parallel/Load balancing": "measured"}),
           "2 ranks, claimed": (2, 1, [], {"Parallel/Load balancing": "claimed"}),
           "2 threads, by body": (1, 2, [], {"Parallel/Thread partition": "by body"}),
           # The same as 2 threads in processes of their own: how far two
           # runs of one configuration differ (an A/A comparison).
           "2 threads, again": (1, 2, [], {}),
           "2 ranks, again": (2, 1, [], {})}


def scene(method, level, steps, work, name, edits):
    prm, levels = CASES[method]
    level = level if level is not None else levels[1]
    dt = 2.5e-4 / 2 ** (level - 4)
    return edit_prm(os.path.join(root, prm), os.path.join(work, name + ".prm"),
                    {"Discretization/Global refinements": str(level),
                     "Time integration/Time step": repr(dt),
                     "Time integration/End time": repr(steps * dt),
                     "Output/Directory": name, "Output/VTU interval": "0",
                     "Output/History interval": "100",
                     "Output/Pressure profile times": "",
                     "Output/Progress interval": "1",
                     "Output/Step times": "true", **edits})


class Run:
    def __init__(self, label, program, prm, work):
        ranks, threads, options, _ = CONFIGS[label]
        self.label = label
        self.out = os.path.join(work, os.path.splitext(os.path.basename(prm))[0])
        self.log = open(self.out + ".log", "w")
        command = [program, prm]
        if ranks > 1:
            command = ["mpirun", "--allow-run-as-root", "-np", str(ranks),
                       "-x", "DEAL_II_NUM_THREADS"] + options + command
        self.process = subprocess.Popen(
            command, cwd=work, stdout=self.log, stderr=subprocess.STDOUT,
            env={**os.environ, "DEAL_II_NUM_THREADS": str(threads)})
        self.program, self.ranks, self.pids = program, ranks, []
        self.windows = []  # (resumed, held) on the monotonic clock

    def stepping(self):
        """Whether the run printed a progress line (set-up done)."""
        with open(self.log.name) as log:
            return re.search(r"^\s*step\s+\d+/\d+", log.read(), re.M) is not None

    def signal(self, number):
        for pid in self.pids:
            try:
                os.kill(pid, number)
            except ProcessLookupError:
                pass

    def set_up(self):
        while not self.stepping():
            if self.process.poll() is not None:
                sys.exit(f"{self.label} ended before its steps:\n"
                         + open(self.log.name).read()[-2000:])
            time.sleep(0.2)
        while len(self.pids) < self.ranks:
            self.pids = program_processes(self.process.pid, self.program)
        self.signal(signal.SIGSTOP)

    def turn(self, seconds):
        if self.process.poll() is not None:
            return
        resumed = time.monotonic()
        self.signal(signal.SIGCONT)
        try:
            self.process.wait(seconds)
        except subprocess.TimeoutExpired:
            self.signal(signal.SIGSTOP)
        self.windows.append((resumed, time.monotonic()))



def step_times(path):
    """The rows of a step_times.csv (step, time, monotonic clock, passes)."""
    with open(path) as table:
        next(table)
        return [[float(x) for x in line.split(",")] for line in table]


def wrapped_command(parser, remainder):
    """The command after `--` of a script that runs one (argparse's
    REMAINDER); a parser error if there is none."""
    command = remainder[1:] if remainder[:1] == ["--"] else remainder
    if not command:
        parser.error("no command (after --)")
    return command


def stalls(rest):
    """The median of `rest` (each step's time outside the passes [s]) and
    the stalls: (step's index, excess over the median [s]) where the excess
    is more than 1 ms."""
    middle = statistics.median(rest)
    return middle, [(k, r - middle) for k, r in enumerate(rest) if r > middle + 1e-3]


def slow_steps(durations, neighbours=25):
    """The slow steps of `durations` (consecutive steps [s]): (step's index,
    excess [s]) where a step is more than 1 ms longer than the median of
    the steps around it (`neighbours` on either side): the step's time
    drifts over a run."""
    found = []
    for k, d in enumerate(durations):
        middle = statistics.median(durations[max(0, k - neighbours):k + neighbours + 1])
        if d > middle + 1e-3:
            found.append((k, d - middle))
    return found


def window_steps(out, windows, overlaps=None):
    """The steps (duration, time in the passes) [s] that began and ended
    inside each window, from out/step_times.csv, the first step of each
    left out (the caches after the other run). With `overlaps`
    (cpu_samples.Overlaps of the turns' samples), only the quiet steps: no
    core taken in them nor in the step before."""
    rows = step_times(os.path.join(out, "step_times.csv"))
    if overlaps:
        from cpu_samples import quiet_steps
        quiet = quiet_steps(rows, overlaps)
    steps = []
    for resumed, held in windows:
        inside = [(b[2] - a[2], b[3], k) for k, (a, b) in enumerate(zip(rows, rows[1:]))
                  if a[2] >= resumed and b[2] <= held]
        steps.append([(s, p) for s, p, k in inside[1:] if not overlaps or quiet[k]])
    return steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--method", choices=list(CASES), default="FEA Q9")
    parser.add_argument("--level", type=int)
    parser.add_argument("--steps", type=int, default=6000)
    parser.add_argument("--window", type=float, default=1.0)
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--serial", action="store_true")
    parser.add_argument("--keep", help="a folder for the runs (kept)")
    parser.add_argument("--also", action="append", default=[],
                        choices=[label for label in CONFIGS if "," in label],
                        help="a further run, against 2 threads too")
    parser.add_argument("--variant", action="append", default=[],
                        metavar="NAME=VARIABLE=VALUE",
                        help="a further 2-rank run with environment variables "
                             "(mpirun -x; VARIABLE=VALUE,... for several), labelled "
                             "'2 ranks, NAME' (repeatable)")
    parser.add_argument("--variant-unbound", action="append", default=[],
                        metavar="NAME=VARIABLE=VALUE",
                        help="as --variant, with mpirun --bind-to none")
    parser.add_argument("--setup-order", choices=["random", "given"], default="random",
                        help="the order in which the runs are set up")
    parser.add_argument("--analyse", metavar="FOLDER",
                        help="only the table of the runs kept in FOLDER")
    parser.add_argument("--against", default="2 threads", metavar="LABEL",
                        help="the run the others are compared with (default: 2 threads)")
    parser.add_argument("--frames", action="store_true",
                        help="print each process's physical contiguity once set up "
                        "(benchmarks/frame_contiguity.py; root)")
    parser.add_argument("--sampled", action="store_true",
                        help="sample every core during the turns (perf, "
                             "benchmarks/cpu_samples.py): the table again over "
                             "the quiet steps")
    args = parser.parse_args()
    if args.analyse:
        analyse(args.analyse, args.against)
        return
    program = os.path.join(args.build, "isoimpact")
    work = os.path.abspath(args.keep or tempfile.mkdtemp(prefix="alternating_"))
    os.makedirs(work, exist_ok=True)
    variants = []
    for variant, options in ([(v, []) for v in args.variant]
                             + [(v, ["--bind-to", "none"]) for v in args.variant_unbound]):
        name, _, settings = variant.partition("=")
        settings = settings.split(",")
        if not name or not all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*=.*", setting)
                               for setting in settings):
            parser.error(f"--variant {variant!r}: expected NAME=VARIABLE=VALUE[,VARIABLE=VALUE]")
        if f"2 ranks, {name}" in CONFIGS:
            parser.error(f"--variant {variant!r}: the run '2 ranks, {name}' exists already")
        CONFIGS[f"2 ranks, {name}"] = (2, 1, [x for setting in settings
                                              for x in ("-x", setting)] + options, {})
        variants.append(f"2 ranks, {name}")
    labels = (["2 threads", "2 ranks"] + args.also + variants
              + (["1 x 1"] if args.serial else []))
    if args.against not in labels:
        parser.error(f"--against {args.against!r}: not among the runs ({', '.join(labels)})")
    # The set-up's order: a run set up later was up to 12 % faster than the
    # same configuration set up first (doc/parallel.md, session 50).
    setup_order = list(labels)
    if args.setup_order == "random":
        random.shuffle(setup_order)
    runs = []
    for label in setup_order:
        name = label.replace(" ", "_").replace(",", "")
        steps = args.steps // 2 if label == "1 x 1" else args.steps
        runs.append(Run(label, program, scene(args.method, args.level, steps, work,
                                              name, CONFIGS[label][3]), work))
        runs[-1].set_up()  # held at its first steps
        print(f"{label}: set up, held", flush=True)
    runs.sort(key=lambda run: labels.index(run.label))  # the turns' order
    frames = {}
    if args.frames:
        from frame_contiguity import describe
        for run in runs:
            frames[run.label] = [describe(pid) for pid in run.pids]
            print(f"{run.label}: frames: " + " | ".join(frames[run.label]), flush=True)
    if args.sampled:
        from cpu_samples import start, stop
        recorder = start(os.path.join(work, "samples.data"))
        time.sleep(1)  # perf's set-up
    turns = 0
    while any(run.process.poll() is None for run in runs):
        order = runs if turns % 2 == 0 else runs[::-1]
        for run in order:
            run.turn(args.window)
        turns += 1
    if args.sampled:
        stop(recorder)
    for run in runs:
        if run.process.wait() != 0:
            sys.exit(f"{run.label} failed:\n" + open(run.log.name).read()[-2000:])
    with open(os.path.join(work, "windows.json"), "w") as record:
        json.dump({"method": args.method, "steps": args.steps, "window": args.window,
                   "rounds": turns, "setup_order": setup_order, "frames": frames,
                   "runs": {run.label: {"out": run.out, "windows": run.windows}
                            for run in runs}}, record, indent=1)
    analyse(work, args.against)


def compare(steps, against, work):
    """Each run's windows' medians and stalls, and each run against the run
    `against` round by round; the windows' means (step, passes) [s]."""
    # Each window's mean step and mean time in the passes (None if empty).
    means = {label: [(statistics.mean(s for s, _ in window),
                      statistics.mean(p for _, p in window)) if window else None
                     for window in windows]
             for label, windows in steps.items()}
    print("the windows' medians [ms per step]: step; passes; rest. Stalls: the steps "
          "whose rest exceeds the run's median rest by more than 1 ms; slow steps: "
          "those more than 1 ms longer than the median of the 50 steps around them "
          "(within the window); the median and the mean of the windows' steps")
    for label, values in means.items():
        values = [x for x in values if x]
        if values:
            every = [s - p for window in steps[label] for s, p in window]
            excess = [1e3 * e for _, e in stalls(every)[1]]
            slow = [1e3 * e for window in steps[label]
                    for _, e in slow_steps([s for s, _ in window])]
            all_steps = [s for window in steps[label] for s, _ in window]
            print(f"  {label}: {statistics.median(1e3 * s for s, _ in values):.3f}; "
                  f"{statistics.median(1e3 * p for _, p in values):.3f}; "
                  f"{statistics.median(1e3 * (s - p) for s, p in values):.3f} "
                  f"({len(values)} windows); stalls {len(excess)} of {len(every)} steps, "
                  f"{sum(excess) / len(every):.3f} ms per step"
                  + (f", each {min(excess):.1f}-{max(excess):.1f} ms (quartiles "
                     f"{' '.join(f'{q:.1f}' for q in statistics.quantiles(excess))})"
                     if len(excess) > 1 else "")
                  + f"; slow steps {len(slow)}, {sum(slow) / len(every):.3f} ms per step"
                  # The typical step against the mean: what the slow steps add.
                  + f"; the steps' median {1e3 * statistics.median(all_steps):.3f} ms, "
                  f"mean {1e3 * statistics.mean(all_steps):.3f} ms")

    def describe(what, values, unit_is_ratio=True):
        interval = median_interval(values, 0.95)
        text = f"{what}: median {statistics.median(values):.4f}"
        if interval:
            text += f", [{interval[0]:.4f}, {interval[1]:.4f}] at {100 * interval[2]:.1f} %"
        if unit_is_ratio:
            text += f", at most 1 in {sum(v <= 1 for v in values)} of {len(values)}"
        else:
            text += f", above 0 in {sum(v > 0 for v in values)} of {len(values)}"
        print(text)

    if against not in means:
        sys.exit(f"no run {against!r} in {work}: {', '.join(means)}")
    for label in [label for label in means if label not in (against, "1 x 1")]:
        pairs = [(a, b) for a, b in zip(means[against], means[label]) if a and b]
        if not pairs:
            continue
        print(f"{label} against {against}, round by round ({len(pairs)} rounds):")
        describe(f"  step, over {against}'", [b[0] / a[0] for a, b in pairs])
        describe(f"  passes, over {against}'", [b[1] / a[1] for a, b in pairs])
        describe(f"  rest, less {against}' [ms]",
                 [1e3 * ((b[0] - b[1]) - (a[0] - a[1])) for a, b in pairs], False)
    # Runs in two processes each (a label and the same label with
    # ", again"; for a variant, --variant "NAME, again=..." too): round by
    # round, the mean step of a run's two processes over that of the two of
    # `against`, which halves the weight of any one process's lasting speed.
    pooled = {label: (label, label + ", again") for label in means
              if label + ", again" in means}
    if against in pooled:
        for label in [label for label in pooled if label != against]:
            both = pooled[against] + pooled[label]
            rounds = [[means[x][k] for x in both]
                      for k in range(min(len(means[x]) for x in both))]
            rounds = [r for r in rounds if all(r)]
            if not rounds:
                continue
            print(f"{label} (both processes) against {against} (both processes), "
                  f"round by round ({len(rounds)} rounds):")
            describe(f"  step, over {against}'",
                     [(r[2][0] + r[3][0]) / (r[0][0] + r[1][0]) for r in rounds])
            describe(f"  passes, over {against}'",
                     [(r[2][1] + r[3][1]) / (r[0][1] + r[1][1]) for r in rounds])
    return means


def analyse(work, against="2 threads"):
    """The table of the runs in `work` (windows.json and the runs'
    step_times.csv), each run against the run `against`."""
    record = json.load(open(os.path.join(work, "windows.json")))
    print(f"{record['method']}, {record['steps']} steps per 2-core run, windows of "
          f"{record['window']} s, {record['rounds']} rounds; runs in {work}")
    if "setup_order" in record:
        print("set up in the order: " + ", ".join(record["setup_order"]))
    steps = {label: window_steps(run["out"], run["windows"])
             for label, run in record["runs"].items()}
    means = compare(steps, against, work)
    samples = os.path.join(work, "samples.data")
    if os.path.exists(samples):
        from cpu_samples import Overlaps, disturbances, load, taken_per_core
        cores = load(samples)
        overlaps = Overlaps(disturbances(cores, "isoimpact"))
        print("the cores taken during each run's windows, per core [ms per s]:")
        for label, run in record["runs"].items():
            away, other = taken_per_core(overlaps, run["windows"], len(cores))
            print(f"  {label}: away (the host) {1e3 * away:.1f}, other tasks {1e3 * other:.1f}")
        print("only the quiet steps (no core taken by another task or the host in "
              "them or the step before; benchmarks/cpu_samples.py):")
        compare({label: window_steps(run["out"], run["windows"], overlaps)
                 for label, run in record["runs"].items()}, against, work)
    if "1 x 1" in means:
        speedups = [a[0] / b[0] for a, b in zip(means["1 x 1"], means["2 ranks"]) if a and b]
        if speedups:
            print(f"speed-up of 2 ranks over 1 x 1 (its step over theirs), round by round: "
                  f"median {statistics.median(speedups):.3f} ({len(speedups)} rounds)")


if __name__ == "__main__":
    main()
