#!/usr/bin/env python3
"""Time per step of the program on 1 rank x 1 thread, 1 rank x 2 threads and
2 MPI ranks x 1 thread (issue 13), FEA Q9 and IGA p2 HRZ at about 1e5 and
1e6 unknowns (the Hertz benchmark, prm/hertz_fea_hrz.prm and
prm/hertz_iga_hrz.prm, at Global refinements 5 and 7, resp. 6 and 8; the
cylinders touch from t = 0, so contact is on). The step is the program's:
time_loop of summary.json less its initial_acceleration_s (the acceleration
at t = 0, once per run), over its steps (no ParaView output, history every
100 steps); the table also gives the initial acceleration and the step with
its share of a run of `--steps` steps. Each configuration runs `--repeats`
times, interleaved with the others; the table gives the median ms per step, the speed-ups against
1 rank x 1 thread (the ratio of the medians, and the median of the ratios
within each round, which a drift of the machine's speed between rounds moves
least), and the memory per process:
- peak resident memory (/usr/bin/time, VmHWM), which counts the pages of the
  shared libraries the process touched (about 130 MB, 75 MB of them
  libdeal.ii, measured with /proc/PID/smaps) in every rank, although the
  ranks share them;
- peak anonymous resident memory (RssAnon of /proc/PID/status, read every
  0.25 s while the run lasts): the process's own data, what a further rank
  adds. It is read in one more run of each configuration, not timed: the
  polling shares the two cores with the runs, and it slows the 2-rank runs,
  which need both cores and wait for the slower rank at every step, more
  than the others (read every 20 ms it took about 8 % of a core). A
  transient shorter than 0.25 s, such as the initial acceleration's
  product, may be missed; heaptrack gives the exact peak heap,
  doc/parallel.md;
- the same with the shared memory's share (Pss_Anon + Pss_Shmem of
  /proc/PID/smaps_rollup, polled alike): the windows both ranks map (the
  bodies' state with Load balancing = shared memory, Open MPI's segments)
  count half per rank, which RssAnon leaves out.

usage: python3 benchmarks/mpi_step_cost.py [--quick | --fine] [--repeats 3] [--steps 200]
                                          [--build build] [--mass HRZ|consistent] [--claimed]
                                          [--by-body] [--measured]
                                          [--method "FEA Q9"|"IGA p2"|"FEA Q9 rigid plane" ...]
  --quick: the 1e5 levels only; --fine: the 1e6 levels only.
  --method "FEA Q9 rigid plane" (only when named): one cylinder on a rigid
    plane, prm/hertz_fea_hrz_rigid_plane.prm at Global refinements 6 and 7
    (1.3e5 and 5.3e5 unknowns), the body split over the ranks.
  --claimed: also 2 ranks with Parallel/Load balancing = claimed.
  --measured: also 2 ranks with Parallel/Load balancing = measured (the
    rows move between the ranks between steps, towards equal pass times;
    the default across nodes and for bodies split over the ranks). The
    2-rank runs without it use the default, automatic: for the two bodies,
    whole on ranks, shared memory here (claimed within the step, the state
    in memory both ranks map, no messages in the step); for the rigid
    plane's split body measured, as with --measured.
  --by-body: also 2 threads with Parallel/Thread partition = by body (each
    body's pass on one thread, the static split of 2 ranks with bodies whole
    on ranks, without messages: what sharing each step's rows as the threads
    come gains on this machine).
The step's time in the bodies' passes (passes_s_per_rank of summary.json,
the ranks' mean, over the steps) and the rest of the step, outside the
passes (the contacts, the waits for the other rank, the step's end), have
columns of their own.
After the table, each configuration's step over that of 2 threads, run by
run (the same round), with the ratios' median and, from 5 rounds on, a
distribution-free interval of at least 90 % confidence for it (the sign
test's order statistics): the machine's speed drifts between runs by more
than the configurations differ, and the interval says what the rounds can
tell apart. The same for the passes alone, and the difference of the time
outside them: where the steps differ.
The table is preceded by the machine's memory bandwidth with 1 and 2 ranks
(benchmarks/memory_bandwidth.cc; build target benchmark_memory_bandwidth):
their ratio is the speed-up of a step bound by memory traffic alone.
  --mass consistent: the consistent mass instead of HRZ (its solve split
    over the ranks by the subtrees of the factor's elimination tree; the
    set-up factorises the mass once per process)."""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(root, "tests", "scripts"))
from testing import edit_prm  # noqa: E402

# File and levels (about 1e5 and 1e6 unknowns).
CASES = {"FEA Q9": ("prm/hertz_fea_hrz.prm", [5, 7]),
         "IGA p2": ("prm/hertz_iga_hrz.prm", [6, 8])}
# Run only when named with --method: one cylinder on a rigid plane, the body
# split over the ranks (its rows near the ranks' interface balanced), about
# 1.3e5 and 5.3e5 unknowns.
NAMED_ONLY = {"FEA Q9 rigid plane": ("prm/hertz_fea_hrz_rigid_plane.prm", [6, 7])}
CONFIGS = [("1 rank x 1 thread", 1, 1, None), ("1 rank x 2 threads", 1, 2, None),
           ("2 ranks x 1 thread", 2, 1, None)]
# --claimed: 2 ranks with Parallel/Load balancing = claimed (the band shared
# within each step) beside the default (automatic: shared memory here for
# bodies whole on ranks, measured for a split body).
CLAIMED = ("2 ranks x 1 thread, claimed", 2, 1, "claimed")
# --measured: 2 ranks with Parallel/Load balancing = measured (the default,
# automatic, is shared memory on one node for bodies whole on ranks).
MEASURED = ("2 ranks x 1 thread, measured", 2, 1, "measured")
# --by-body: 2 threads with Parallel/Thread partition = by body (each body's
# pass on one thread: the static split of 2 ranks with bodies whole on ranks,
# without messages).
BY_BODY = ("1 rank x 2 threads, by body", 1, 2, "by body")
# The parameter each variant sets.
VARIANT_EDITS = {"claimed": {"Parallel/Load balancing": "claimed"},
                 "measured": {"Parallel/Load balancing": "measured"},
                 "by body": {"Parallel/Thread partition": "by body"}}


def benchmark_prm(prm, level, steps, work, mass="HRZ", variant=None):
    """The scene at `level` for `steps` steps, written to work/run.prm (with
    a `variant` of VARIANT_EDITS: run_<variant>.prm with its parameter):
    dt = 2.5e-4 s at level 4, halved per level (stable), inside the impact;
    output to work/out without ParaView records, history every 100 steps."""
    dt = 2.5e-4 / 2 ** (level - 4)
    edits = VARIANT_EDITS[variant] if variant else {}
    name = f"run_{variant.replace(' ', '_')}.prm" if variant else "run.prm"
    return edit_prm(os.path.join(root, prm), os.path.join(work, name),
                    {**edits,
                     "Discretization/Global refinements": str(level),
                     "Time integration/Time step": repr(dt),
                     "Time integration/End time": repr(steps * dt),
                     "Output/Directory": "out", "Output/VTU interval": "0",
                     "Output/History interval": "100",
                     "Output/Pressure profile times": "",
                     "Output/Progress interval": "100",
                     "Mass matrix/Scheme": mass})


def program_processes(top_pid, program):
    """The processes of `program` (by name) among top_pid and its
    descendants."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as stat:
                    parents[int(entry)] = int(stat.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    name = os.path.basename(program)[:15]
    found = []
    for pid in parents:
        ancestor = pid
        while ancestor in parents and ancestor != top_pid:
            ancestor = parents[ancestor]
        if ancestor != top_pid:
            continue
        try:
            with open(f"/proc/{pid}/comm") as comm:
                if comm.read().strip() == name:
                    found.append(pid)
        except OSError:
            pass
    return found


def peak_anonymous_memory(top_pid, program, stop, peaks):
    """Polls every process of `program` below top_pid until `stop` is set;
    peaks[pid] is the largest value seen (bytes) of its RssAnon and of its
    Pss_Anon + Pss_Shmem (/proc/PID/smaps_rollup: the shared memory's pages
    counted in shares, half per rank where 2 ranks map them)."""
    while not stop.is_set():
        for pid in program_processes(top_pid, program):
            try:
                with open(f"/proc/{pid}/status") as status:
                    anon = re.search(r"^RssAnon:\s*(\d+) kB", status.read(), re.M)
                with open(f"/proc/{pid}/smaps_rollup") as rollup:
                    text = rollup.read()
                shares = [re.search(rf"^{field}:\s*(\d+) kB", text, re.M)
                          for field in ("Pss_Anon", "Pss_Shmem")]
            except OSError:
                continue
            if anon and all(shares):
                old = peaks.get(pid, (0, 0))
                peaks[pid] = (max(old[0], int(anon.group(1)) * 1024),
                              max(old[1], sum(int(m.group(1)) for m in shares) * 1024))
        time.sleep(0.25)


def run(program, prm, work, ranks, threads, poll_memory=False):
    out = os.path.join(work, "out")
    shutil.rmtree(out, ignore_errors=True)
    # Each process appends its line to a file of its own lines (on stderr
    # the ranks' lines could interleave).
    peak_file = os.path.join(work, "peak_rss.txt")
    if os.path.exists(peak_file):
        os.remove(peak_file)
    command = ["/usr/bin/time", "-a", "-o", peak_file, "-f", "PEAK_RSS_KB %M",
               program, prm]
    env = {**os.environ, "DEAL_II_NUM_THREADS": str(threads)}
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
                   "-x", "DEAL_II_NUM_THREADS"] + command
    process = subprocess.Popen(command, cwd=work, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    stop, anonymous = threading.Event(), {}
    poller = threading.Thread(target=peak_anonymous_memory,
                              args=(process.pid, program, stop, anonymous))
    if poll_memory:
        poller.start()
    stdout, stderr = process.communicate()
    stop.set()
    if poll_memory:
        poller.join()
    if process.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{stdout[-2000:]}\n{stderr[-2000:]}")
    summary = json.load(open(os.path.join(out, "summary.json")))
    peak_lines = open(peak_file).read() if os.path.exists(peak_file) else ""
    rss = [int(v) * 1024 for v in re.findall(r"PEAK_RSS_KB (\d+)", peak_lines)]
    if len(rss) != ranks:
        print(f"peak memory of {len(rss)} of {ranks} processes from /usr/bin/time: "
              f"{peak_lines[-500:]}", file=sys.stderr)
    # The steps alone: the time loop less the initial acceleration (once
    # per run; its share of a short run's loop is not a step's cost).
    # Every configuration: the time per step in the bodies' passes
    # (passes_s_per_rank, the ranks' mean). 2 ranks: each rank's time per
    # step outside its passes (the steps less its passes, over the steps):
    # its contact, its waits, the step's end (against rank 0's time loop,
    # the one summary.json gives).
    initial = summary["initial_acceleration_s"]
    loop, steps = summary["wall_time_parts_s"]["time_loop"] - initial, summary["steps"]
    passes = statistics.mean(summary["passes_s_per_rank"]) / steps
    outside = ([(loop - p) / steps for p in summary["passes_s_per_rank"]]
               if ranks == 2 else [])
    return (loop / steps,
            max(rss) if rss else float("nan"),
            (max(a for a, _ in anonymous.values()) if anonymous else float("nan"),
             max(p for _, p in anonymous.values()) if anonymous else float("nan")),
            summary["unknowns"],
            summary.get("rank_splits", []),
            [w / summary["steps"] for w in summary.get("mpi_wait_s_per_rank", [])],
            outside, initial, passes)


def describe_splits(splits, step, waits, outside=()):
    """The load balancing of a run on 2 ranks: each body's final split
    (layers; its bounds; claimed balancing: the band's chunks and how many
    of them rank 0 computed in the last pass), its moves, the ranks' averaged pass times per
    row that chose it, and each rank's pass per step from them (the sum over
    the bodies of time per row x owned rows; averaged over about the last
    twenty steps) against the run's time per step `step` (s): what is left
    is the rank's work outside the pass and its waiting. Then each rank's
    waits for the other's messages per step (`waits`, s; mpi_wait_s_per_rank
    of summary.json over the steps), and each rank's time per step outside
    its passes (`outside`, s; see run())."""
    parts = []
    for split in splits:
        if not split.get("load_balancing"):
            continue
        low, high = split["split_bounds_layers"]
        if split.get("claims_band"):
            parts.append(f"{split['body']} band of {split['band_chunks']} chunks, "
                         f"{split['band_chunks_of_rank_0']} of them rank 0's in the last pass")
            continue
        parts.append(f"{split['body']} split {split['split_layers']} of [{low}, {high}], "
                     f"{split['moves']} moves, owned {split['owned_unknowns_per_rank']}")
    claimed = any(split.get("claims_band") for split in splits)
    if parts and claimed and splits[0].get("pass_time_per_row_s"):
        parts.append("ns per row " + "/".join(
            f"{1e9 * c:.1f}" for c in splits[0]["pass_time_per_row_s"]))
    if parts and not claimed and splits[0].get("pass_time_per_row_s"):
        parts.append("ns per row " + "/".join(
            f"{1e9 * c:.1f}" for c in splits[0]["pass_time_per_row_s"]))
        passes = [sum(split["pass_time_per_row_s"][p] * split["owned_unknowns_per_rank"][p]
                      for split in splits if split.get("pass_time_per_row_s"))
                  for p in range(2)]
        parts.append("pass per step " + "/".join(f"{1e3 * t:.2f}" for t in passes) +
                     f" ms of {1e3 * step:.2f} ms")
    if parts and waits:
        parts.append("waits per step " + "/".join(f"{1e3 * w:.2f}" for w in waits) + " ms")
    if parts and outside:
        parts.append("outside the passes per step " +
                     "/".join(f"{1e3 * t:.2f}" for t in outside) + " ms")
    return "; ".join(parts)


def bandwidth(build, ranks):
    """Read and triad bandwidth summed over `ranks` ranks streaming at the
    same time (benchmarks/memory_bandwidth.cc), GB/s."""
    command = [os.path.join(build, "benchmarks", "benchmark_memory_bandwidth")]
    if ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
                   "-x", "DEAL_II_NUM_THREADS"] + command
    out = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    match = re.search(r"read_GB_per_s_total ([0-9.]+) triad_GB_per_s_total ([0-9.]+)", out)
    return float(match.group(1)), float(match.group(2))


def print_bandwidth_ratio(build, repeats):
    """The ratio of the bandwidths of 2 ranks and 1 rank (each round's ratio
    taken, paired, and their median printed): the speed-up of a step bound
    by memory traffic alone. A step that one core runs below the bandwidth
    it can draw (latency, arithmetic) scales beyond it."""
    rounds = [(bandwidth(build, 1), bandwidth(build, 2)) for _ in range(repeats)]
    for kernel, k in [("read", 0), ("triad", 1)]:
        one = [r[0][k] for r in rounds]
        two = [r[1][k] for r in rounds]
        ratio = statistics.median(b / a for a, b in zip(one, two))
        print(f"- memory bandwidth, {kernel}: 1 rank {statistics.median(one):.1f} GB/s, "
              f"2 ranks {statistics.median(two):.1f} GB/s together; ratio (paired "
              f"median) {ratio:.2f} "
              f"(runs: {', '.join(f'{a:.1f}/{b:.1f}' for a, b in zip(one, two))})",
              flush=True)


def median_interval(values, confidence=0.9):
    """A distribution-free interval of the median of `values` (the sign
    test's): the order statistics x_(k) and x_(n+1-k), with the largest k
    such that P(B < k) <= (1 - confidence) / 2 for B ~ Binomial(n, 1/2).
    Returns (low, high, its coverage 1 - 2 P(B < k)), or None when n is too
    small for the confidence (n < 5 at 90 %)."""
    x, n = sorted(values), len(values)
    below = 0.  # P(B < k)
    k = 0
    while k < n and below + math.comb(n, k) / 2 ** n <= (1 - confidence) / 2:
        below += math.comb(n, k) / 2 ** n
        k += 1
    if k == 0:
        return None
    return x[k - 1], x[n - k], 1 - 2 * below


def describe_ratios(ratios):
    """The run-by-run ratios' median, its 90 % interval and how many are at
    most 1."""
    text = (f"median {statistics.median(ratios):.3f}; "
            f"no slower in {sum(r <= 1 for r in ratios)} of {len(ratios)}")
    interval = median_interval(ratios)
    if interval:
        text += (f"; the median within [{interval[0]:.3f}, {interval[1]:.3f}] "
                 f"at {100 * interval[2]:.1f} % confidence (sign test)")
    return text


def main():
    parser = argparse.ArgumentParser()
    level_choice = parser.add_mutually_exclusive_group()
    level_choice.add_argument("--quick", action="store_true")
    level_choice.add_argument("--fine", action="store_true")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--build", default=os.path.join(root, "build"))
    parser.add_argument("--mass", choices=["HRZ", "consistent"], default="HRZ")
    parser.add_argument("--claimed", action="store_true",
                        help="also 2 ranks with Load balancing = claimed")
    parser.add_argument("--measured", action="store_true",
                        help="also 2 ranks with Load balancing = measured")
    parser.add_argument("--by-body", action="store_true",
                        help="also 2 threads with Thread partition = by body")
    parser.add_argument("--method", choices=list(CASES) + list(NAMED_ONLY),
                        action="append",
                        help="only this method (repeatable; default: FEA Q9 and "
                             "IGA p2)")
    args = parser.parse_args()
    configs = (CONFIGS + ([CLAIMED] if args.claimed else []) +
               ([MEASURED] if args.measured else []) +
               ([BY_BODY] if args.by_body else []))
    program = os.path.join(args.build, "isoimpact")
    for tool in ["/usr/bin/time", "mpirun"]:
        if not shutil.which(tool):
            sys.exit(f"{tool} is needed (Debian: apt-get install time openmpi-bin)")
    print_bandwidth_ratio(args.build, max(args.repeats, 3))
    print()
    print("| method | level | unknowns | configuration | step [ms] (median) | all runs [ms] "
          "| speed-up vs 1 x 1 | speed-up (paired median) | initial acceleration [ms] (median) "
          "| step with the initial acceleration's share [ms] (median) "
          "| passes per step [ms] (median) | outside the passes per step [ms] (median) "
          "| peak memory per process [MB] | memory vs 1 x 1 "
          "| peak anonymous memory per process [MB] | anonymous vs 1 x 1 "
          "| peak anonymous and shared memory's share per process [MB] | the same vs 1 x 1 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    notes = []
    with tempfile.TemporaryDirectory() as work:
        for method, (prm, levels) in {**CASES, **NAMED_ONLY}.items():
            if method in NAMED_ONLY and method not in (args.method or []):
                continue
            if args.method and method not in args.method:
                continue
            chosen = levels[:1] if args.quick else levels[1:] if args.fine else levels
            for level in chosen:
                edited = {variant: benchmark_prm(prm, level, args.steps, work, args.mass,
                                                 variant)
                          for _, _, _, variant in configs}
                times = {name: [] for name, _, _, _ in configs}
                initials = {name: [] for name, _, _, _ in configs}
                passes = {name: [] for name, _, _, _ in configs}
                memory, anonymous = {}, {}
                unknowns = 0
                notes_of_level = []
                for _ in range(args.repeats):
                    for name, ranks, threads, variant in configs:
                        step, rss, _, unknowns, splits, waits, outside, initial, passed = run(
                            program, edited[variant], work, ranks, threads)
                        times[name].append(step)
                        passes[name].append(passed)
                        initials[name].append(initial)
                        memory[name] = rss
                        described = describe_splits(splits, step, waits, outside)
                        if ranks == 2 and described:
                            notes_of_level.append(f"{name}, {1e3 * step:.2f} ms: "
                                                  f"{described}")
                # The anonymous memory in runs of its own (see above).
                for name, ranks, threads, variant in configs:
                    anonymous[name] = run(program, edited[variant], work, ranks, threads,
                                          poll_memory=True)[2]
                base = statistics.median(times[CONFIGS[0][0]])
                for name, _, _, _ in configs:
                    median = statistics.median(times[name])
                    paired = statistics.median(
                        b / t for b, t in zip(times[CONFIGS[0][0]], times[name]))
                    print(f"| {method} {args.mass} | {level} | {unknowns} | {name} | {1e3 * median:.2f} | "
                          f"{', '.join(f'{1e3 * t:.2f}' for t in times[name])} | "
                          f"{base / median:.2f} | {paired:.2f} | "
                          f"{1e3 * statistics.median(initials[name]):.1f} | "
                          f"{1e3 * statistics.median(t + i / args.steps for t, i in zip(times[name], initials[name])):.2f} | "
                          f"{1e3 * statistics.median(passes[name]):.2f} | "
                          f"{1e3 * statistics.median(t - p for t, p in zip(times[name], passes[name])):.3f} | "
                          f"{memory[name] / 1e6:.0f} | "
                          f"{memory[name] / memory[CONFIGS[0][0]]:.2f} | "
                          f"{anonymous[name][0] / 1e6:.0f} | "
                          f"{anonymous[name][0] / anonymous[CONFIGS[0][0]][0]:.2f} | "
                          f"{anonymous[name][1] / 1e6:.0f} | "
                          f"{anonymous[name][1] / anonymous[CONFIGS[0][0]][1]:.2f} |",
                          flush=True)
                # Against 2 threads, run by run (same round, one after the
                # other): each other configuration's step over theirs.
                threads = CONFIGS[1][0]
                notes_of_level.extend(
                    f"{name} / {threads}, run by run: "
                    + ", ".join(f"{t / u:.3f}" for t, u in zip(times[name], times[threads]))
                    + f" ({describe_ratios([t / u for t, u in zip(times[name], times[threads])])})"
                    for name, _, _, _ in configs if name not in (CONFIGS[0][0], threads))
                # The same for the passes alone, and the difference of the
                # time outside them (ms per step): where the steps differ.
                for name, _, _, _ in configs:
                    if name in (CONFIGS[0][0], threads):
                        continue
                    ratios = [p / q for p, q in zip(passes[name], passes[threads])]
                    notes_of_level.append(
                        f"{name} / {threads}, the passes alone, run by run: "
                        + ", ".join(f"{r:.3f}" for r in ratios)
                        + f" ({describe_ratios(ratios)})")
                    differences = [1e3 * ((t - p) - (u - q)) for t, p, u, q in
                                   zip(times[name], passes[name], times[threads],
                                       passes[threads])]
                    interval = median_interval(differences)
                    notes_of_level.append(
                        f"{name} - {threads}, outside the passes [ms per step], run by run: "
                        + ", ".join(f"{d:.3f}" for d in differences)
                        + f" (median {statistics.median(differences):.3f}"
                        + (f", within [{interval[0]:.3f}, {interval[1]:.3f}] at "
                           f"{100 * interval[2]:.1f} %" if interval else "") + ")")
                # (After the table: the load balancing of each 2-rank run.)
                notes.extend(f"- {method} level {level}, {line}" for line in notes_of_level)
    if notes:
        print()
        print("\n".join(notes))


if __name__ == "__main__":
    main()
