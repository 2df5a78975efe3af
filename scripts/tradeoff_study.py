#!/usr/bin/env python3
"""The speed-accuracy trade of the Hertz benchmark (doc/tradeoff.md) and the
table of every mass scheme with every chatter remedy (doc/results.md).

Runs the benchmark for every combination of refinement level x family (FEA
Q9, FEA Q8, IGA p2, IGA p3) x mass scheme (consistent, row-sum, HRZ) x
remedy (plain penalty, contact damping, ...), each at the automatic stable
time step, VTU output off, one run at a time (timings on a quiet machine).
Per run: unknowns, time step, steps, wall time of the time loop, peak memory
(maximum resident set, /usr/bin/time), and the errors

- against the reference: force trend peak against the converged 430.7 N/m,
  contact duration against the analytic 0.749 s, L2 of the force trend over
  the contact against the analytic (quasi-static) force history, maximal-
  pressure trend peak against the analytic p0, profile RMS against the
  Hertz profile at t = 0.375 s (in % of p0);
- against the finest run of its family (same family, mass and remedy): the
  same measures, the profile against the finest run's profile;
- the force chatter (an error in itself: 0 for a smooth history).

Writes OUTPUT_DIR/tradeoff.csv, OUTPUT_DIR/tradeoff.md (the table, the
Pareto fronts' members and the advice) and OUTPUT_DIR/fig_pareto.png (one
panel per error measure against the time-loop wall time, the non-dominated
runs marked); with a single level also OUTPUT_DIR/fig_remedies.png (the
remedies side by side per family and mass scheme). A run the program refuses (e.g. row-sum with Q8: negative
corner masses) is listed with its status and left out of the fronts.

usage: python3 scripts/tradeoff_study.py PROGRAM OUTPUT_DIR
         [--levels 2 3 4 5 6] [--families "FEA Q9" "FEA Q8" "IGA p2" "IGA p3"]
         [--masses consistent row-sum HRZ] [--remedies plain damping [bipenalty] [redistribution]]
         [--end-time 0.9] [--skip-run] [--reuse]
The defaults are the full study (doc/tradeoff.md says how long it takes)."""
import argparse
import csv
import json
import os
import subprocess
import sys
import time as clock

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
sys.path.insert(0, HERE)
from testing import edit_prm  # noqa: E402
from isoimpact_results import (hertz_support, moving_average, read_history, read_profile,  # noqa: E402
                               window_width)

TREND_WINDOW_S = 0.05
PROFILE_TIME_S = 0.375
# The shared references of the project (README): the converged dynamic
# trend peak and the analytic (Hertz, Gerl-Zippelius) duration and p0.
REFERENCE_TREND_PEAK_N_PER_M = 430.7
REFERENCE_DURATION_S = 0.749
REFERENCE_P0_PA = 197.7

FAMILIES = {
    "FEA Q9": ("prm/hertz_fea_hrz.prm", {}),
    "FEA Q8": ("prm/hertz_fea_q8_hrz.prm", {}),
    "IGA p2": ("prm/hertz_iga_hrz.prm", {}),
    "IGA p3": ("prm/hertz_iga_hrz.prm", {"Discretization/Degree": "3"}),
}
MASSES = ["consistent", "row-sum", "HRZ"]
# Each remedy as the parameter edits that switch it on (doc/formulation.md).
REMEDIES = {
    "plain": {},
    "damping": {"Contact/Damping ratio": "0.2"},
    # Lumped mass only: the program refuses it with the consistent mass.
    "bipenalty": {"Contact/Bipenalty": "true"},
    "redistribution": {"Contact/Mass redistribution": "true"},
}
# The error measures: (csv column, axis label), each in %.
MEASURES = [
    ("force_peak_error_percent", "force trend peak error (%)"),
    ("duration_error_percent", "contact duration error (%)"),
    ("force_l2_vs_reference_run_percent", "L2 error of the force trend (%)"),
    ("pressure_peak_error_percent", "max-pressure trend peak error (%)"),
    ("profile_rms_percent_p0", "pressure profile RMS (% of p0)"),
    ("force_chatter_percent", "force chatter (%)"),
]


def run_name(level, family, mass, remedy):
    return f"L{level}_{family.replace(' ', '_')}_{mass}_{remedy}"


def run(program, work, level, family, mass, remedy, end_time):
    """Runs one configuration in work/<name>; returns its status."""
    name = run_name(level, family, mass, remedy)
    directory = os.path.join(work, name)
    base, family_edits = FAMILIES[family]
    edits = {"Discretization/Global refinements": str(level),
             "Mass matrix/Scheme": mass,
             "Time integration/Time step": "auto",
             "Time integration/Allow time step above the stable estimate": "false",
             "Time integration/End time": str(end_time),
             "Output/Directory": directory,
             "Output/History interval": "1",
             "Output/VTU interval": "0",
             "Output/Pressure profile times": str(PROFILE_TIME_S),
             "Output/Analytic reference": "Gerl-Zippelius",
             "Output/Progress interval": "100"}
    edits.update(family_edits)
    edits.update(REMEDIES[remedy])
    prm = edit_prm(os.path.join(ROOT, base), os.path.join(work, name + ".prm"), edits)
    memory_file = os.path.join(work, name + ".rss_kB")
    with open(os.path.join(work, name + ".log"), "w") as log:
        status = subprocess.call(["/usr/bin/time", "-f", "%M", "-o", memory_file,
                                  program, prm], stdout=log, stderr=subprocess.STDOUT)
    return status


def time_loop_seconds(summary):
    """The time loop's wall time: summary.json's wall_time_parts_s.time_loop
    where the program reports the parts, else the whole run's wall time."""
    parts = summary.get("wall_time_parts_s")
    return float(parts["time_loop"] if parts else summary["wall_time_s"])


def trend_of(history):
    dt = float(np.median(np.diff(history["time"])))
    return moving_average(history["contact_force"], window_width(TREND_WINDOW_S, dt))


def contact_window(force):
    active = np.flatnonzero(force > 0)
    mask = np.zeros(len(force), dtype=bool)
    if len(active):
        mask[active[0]:active[-1] + 1] = True
    return mask


def relative_l2(time, signal, reference_time, reference, mask):
    """||signal - reference|| / ||reference|| over the masked reference
    samples, the signal interpolated to the reference's times."""
    values = np.interp(reference_time[mask], time, signal)
    return float(np.linalg.norm(values - reference[mask]) / np.linalg.norm(reference[mask]))


def profile_rms(profile, reference_position, reference_pressure, a, p0):
    """RMS over |x| < 0.9 a of the profile's consistent pressure minus the
    reference (interpolated to the profile's points), in % of p0."""
    mask = np.abs(profile["position"]) < 0.9 * a
    reference = np.interp(profile["position"][mask], reference_position, reference_pressure)
    return 100 * float(np.sqrt(np.mean((profile["pressure"][mask] - reference) ** 2))) / p0


def collect(work, level, family, mass, remedy):
    """The raw measures of one run (None entries where it did not complete)."""
    name = run_name(level, family, mass, remedy)
    directory = os.path.join(work, name)
    row = {"run": name, "level": level, "family": family, "mass": mass, "remedy": remedy}
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        row["status"] = "not run"
        log = os.path.join(work, name + ".log")
        if os.path.exists(log):
            lines = [line.strip() for line in open(log) if line.strip()]
            row["status"] = "stopped: " + (lines[-1][:120] if lines else "")
        return row
    with open(summary_path) as f:
        summary = json.load(f)
    row["status"] = summary["status"]
    history = read_history(directory)
    trend = trend_of(history)
    force = history["contact_force"]
    mask = contact_window(force)
    peak = float(np.max(trend))
    dt = float(summary["time_step_s"])
    pressure_trend = moving_average(history["max_contact_pressure"],
                                    window_width(TREND_WINDOW_S, dt))
    memory_file = os.path.join(work, name + ".rss_kB")
    memory = float(open(memory_file).read().split()[-1]) * 1024 if os.path.exists(memory_file) else None
    row.update({
        "unknowns": summary["unknowns"], "time_step_s": dt, "steps": summary["steps"],
        "time_loop_s": time_loop_seconds(summary),
        "peak_memory_MB": memory / 2**20 if memory else None,
        "force_trend_peak_N_per_m": peak,
        "contact_duration_s": summary["contact_duration_s"],
        "pressure_trend_peak_Pa": float(np.max(pressure_trend)),
        "force_chatter_percent": 100 * float(np.sqrt(np.mean((force - trend)[mask] ** 2))) / peak,
        "energy_error_percent": 100 * float(np.max(np.abs(history["total_energy"] -
                                                         history["total_energy"][0])) /
                                            history["total_energy"][0]),
    })
    row["_time"], row["_trend"], row["_mask"] = history["time"], trend, mask
    row["_analytic_force"] = history.get("analytic_contact_force")
    row["_profile"] = read_profile(directory, PROFILE_TIME_S)
    return row


def add_errors(rows):
    """The errors against the reference and against the finest run of each
    family (same family, mass and remedy)."""
    finest = {}
    for r in rows:
        if r.get("status") == "completed":
            key = (r["family"], r["mass"], r["remedy"])
            if key not in finest or r["level"] > finest[key]["level"]:
                finest[key] = r
    for r in rows:
        if r.get("status") != "completed":
            continue
        r["force_peak_error_percent"] = 100 * abs(r["force_trend_peak_N_per_m"] /
                                                  REFERENCE_TREND_PEAK_N_PER_M - 1)
        r["duration_error_percent"] = 100 * abs(r["contact_duration_s"] / REFERENCE_DURATION_S - 1)
        r["pressure_peak_error_percent"] = 100 * abs(r["pressure_trend_peak_Pa"] / REFERENCE_P0_PA - 1)
        analytic = r["_analytic_force"]
        if analytic is not None:
            mask = analytic > 0
            r["force_l2_error_percent"] = 100 * relative_l2(r["_time"], r["_trend"], r["_time"],
                                                            analytic, mask)
        profile = r["_profile"]
        if profile is not None:
            a, p0 = hertz_support(profile)
            r["profile_rms_percent_p0"] = profile_rms(profile, profile["position"],
                                                      profile["analytic_pressure"], a, p0)
        f = finest[(r["family"], r["mass"], r["remedy"])]
        r["finest_level"] = f["level"]
        if f is r:
            continue
        r["force_peak_vs_finest_percent"] = 100 * abs(r["force_trend_peak_N_per_m"] /
                                                      f["force_trend_peak_N_per_m"] - 1)
        r["duration_vs_finest_percent"] = 100 * abs(r["contact_duration_s"] /
                                                    f["contact_duration_s"] - 1)
        r["pressure_peak_vs_finest_percent"] = 100 * abs(r["pressure_trend_peak_Pa"] /
                                                         f["pressure_trend_peak_Pa"] - 1)
        r["force_l2_vs_finest_percent"] = 100 * relative_l2(r["_time"], r["_trend"], f["_time"],
                                                            f["_trend"], f["_mask"])
        if profile is not None and f["_profile"] is not None:
            a, p0 = hertz_support(f["_profile"])
            r["profile_rms_vs_finest_percent_p0"] = profile_rms(
                profile, f["_profile"]["position"], f["_profile"]["pressure"], a, p0)
    # the force trend against one common reference run: the finest level's
    # run with the least chatter (the analytic force is quasi-static: every
    # run is 11-14 % off it, the dynamics, doc/results.md)
    done = [r for r in rows if r.get("status") == "completed"]
    if done:
        top = max(r["level"] for r in done)
        reference = min((r for r in done if r["level"] == top),
                        key=lambda r: r["force_chatter_percent"])
        for r in done:
            r["reference_run"] = reference["run"]
            if r is not reference:
                r["force_l2_vs_reference_run_percent"] = 100 * relative_l2(
                    r["_time"], r["_trend"], reference["_time"], reference["_trend"],
                    reference["_mask"])
    # cost per step against plain HRZ of the same family and level
    plain = {(r["family"], r["level"]): r for r in rows
             if r.get("status") == "completed" and r["mass"] == "HRZ" and r["remedy"] == "plain"}
    for r in rows:
        base = plain.get((r["family"], r["level"]))
        if r.get("status") == "completed" and base is not None:
            r["step_cost_vs_plain_hrz"] = (r["time_loop_s"] / r["steps"]) / \
                (base["time_loop_s"] / base["steps"])


COLUMNS = ["run", "level", "family", "mass", "remedy", "status", "unknowns", "time_step_s", "steps",
           "time_loop_s", "peak_memory_MB", "step_cost_vs_plain_hrz",
           "force_trend_peak_N_per_m", "contact_duration_s", "pressure_trend_peak_Pa",
           "force_chatter_percent", "energy_error_percent",
           "force_peak_error_percent", "duration_error_percent", "force_l2_error_percent",
           "pressure_peak_error_percent", "profile_rms_percent_p0",
           "finest_level", "force_peak_vs_finest_percent", "duration_vs_finest_percent",
           "force_l2_vs_finest_percent", "pressure_peak_vs_finest_percent",
           "profile_rms_vs_finest_percent_p0", "reference_run",
           "force_l2_vs_reference_run_percent"]


def pareto(points):
    """Indices of the non-dominated (cost, error) points (both minimised)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def fronts(rows):
    """{measure: [rows on its front, by increasing cost]}."""
    done = [r for r in rows if r.get("status") == "completed"]
    result = {}
    for column, _ in MEASURES:
        candidates = [r for r in done if r.get(column) is not None]
        front = pareto([(r["time_loop_s"], r[column]) for r in candidates])
        result[column] = [candidates[i] for i in front]
    return result


def plot(rows, front, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    done = [r for r in rows if r.get("status") == "completed"]
    markers = {"FEA Q9": "o", "FEA Q8": "s", "IGA p2": "^", "IGA p3": "v"}
    colours = {"consistent": "tab:blue", "row-sum": "tab:orange", "HRZ": "tab:green"}
    fig, axes = plt.subplots(2, 3, figsize=(15, 9))
    for ax, (column, label) in zip(axes.flat, MEASURES):
        for r in done:
            if r.get(column) is None:
                continue
            ax.scatter(r["time_loop_s"], max(r[column], 1e-3), marker=markers[r["family"]],
                       facecolors="none" if r["remedy"] == "plain" else colours[r["mass"]],
                       edgecolors=colours[r["mass"]], s=30)
        members = front[column]
        ax.plot([r["time_loop_s"] for r in members], [max(r[column], 1e-3) for r in members],
                "k-", lw=1, label="non-dominated")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the time loop (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    handles = [plt.Line2D([], [], marker=m, ls="", color="k", mfc="none", label=f)
               for f, m in markers.items()]
    handles += [plt.Line2D([], [], marker="o", ls="", color=c, label=m) for m, c in colours.items()]
    handles += [plt.Line2D([], [], marker="o", ls="", color="grey", mfc="none", label="plain penalty"),
                plt.Line2D([], [], marker="o", ls="", color="grey", label="with a remedy"),
                plt.Line2D([], [], color="k", label="non-dominated")]
    fig.legend(handles=handles, loc="lower center", ncol=6)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=90)


def plot_remedies(rows, path):
    """One level: the remedies side by side for every family and mass
    scheme (chatter, pressure errors, step cost against plain HRZ)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    done = [r for r in rows if r.get("status") == "completed"]
    groups = sorted({(r["family"], r["mass"]) for r in done})
    remedies = sorted({r["remedy"] for r in done}, key=list(REMEDIES).index)
    panels = [("force_chatter_percent", "force chatter (%)", 3.0),
              ("pressure_peak_error_percent", "max-pressure trend peak error (%)", 10.0),
              ("profile_rms_percent_p0", "pressure profile RMS (% of p0)", 10.0),
              ("step_cost_vs_plain_hrz", "cost per step / plain HRZ", 1.5)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(max(8, 1.1 * len(groups)), 11), sharex=True)
    width = 0.8 / max(1, len(remedies))
    for ax, (column, label, target) in zip(axes, panels):
        for k, remedy in enumerate(remedies):
            values = []
            for g in groups:
                match = [r for r in done if (r["family"], r["mass"]) == g and r["remedy"] == remedy]
                values.append(match[0].get(column) if match and match[0].get(column) is not None
                              else float("nan"))
            ax.bar([i + (k - (len(remedies) - 1) / 2) * width for i in range(len(groups))],
                   values, width, label=remedy)
        ax.axhline(target, color="k", ls="--", lw=1)
        ax.set_ylabel(label)
        ax.set_yscale("log")
        ax.grid(True, axis="y", which="both", alpha=0.3)
    axes[0].legend(ncol=len(remedies))
    axes[-1].set_xticks(range(len(groups)))
    axes[-1].set_xticklabels([f"{f}\n{m}" for f, m in groups])
    axes[0].set_title(f"level {done[0]['level']}: remedies (dashed: the issue's targets)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def fmt(value, digits=3):
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def cheapest(rows, column, limit):
    """The cheapest run whose error, and that of every finer run of its
    family (same family, mass and remedy), is within the limit: a coarse
    run that meets it by a lucky cancellation does not count."""
    done = [r for r in rows if r.get("status") == "completed" and r.get(column) is not None]

    def holds(r):
        return all(q[column] <= limit for q in done
                   if (q["family"], q["mass"], q["remedy"]) == (r["family"], r["mass"], r["remedy"])
                   and q["level"] >= r["level"])
    ok = [r for r in done if holds(r)]
    return min(ok, key=lambda r: r["time_loop_s"]) if ok else None


def describe(r):
    return f"{r['family']} {r['mass']} {r['remedy']}, level {r['level']} ({r['unknowns']} unknowns)"


def write_markdown(rows, front, path, command):
    lines = [f"Generated by `{command}`.", "",
             "Errors in %: force trend peak against the converged 430.7 N/m, duration against "
             "the analytic 0.749 s, maximal-pressure trend peak against p0 = 197.7 Pa, profile "
             "RMS against the Hertz profile at t = 0.375 s (% of p0), the L2 error of the force "
             "trend over the contact against the reference run "
             f"{next((r['reference_run'] for r in rows if r.get('reference_run')), '-')}. "
             "The advice takes the cheapest run that meets the goal together with every finer "
             "run of its family (same element, mass and remedy).", ""]
    lines += ["## Advice", "", "| goal | cheapest configuration | time loop (s) | its error |",
              "|---|---|---|---|"]
    goals = [("force trend peak error below 1 %", "force_peak_error_percent", 1.0),
             ("L2 error of the force trend below 2 %", "force_l2_vs_reference_run_percent", 2.0),
             ("max-pressure trend peak error below 10 %", "pressure_peak_error_percent", 10.0),
             ("pressure profile RMS below 10 % of p0", "profile_rms_percent_p0", 10.0),
             ("force chatter below 3 %", "force_chatter_percent", 3.0)]
    for goal, column, limit in goals:
        r = cheapest(rows, column, limit)
        lines.append(f"| {goal} | " + (f"{describe(r)} | {fmt(r['time_loop_s'])} | "
                                       f"{fmt(r[column])} |" if r else "none of the runs | - | - |"))
    lines += ["", "## Non-dominated runs per error measure (by increasing cost)", ""]
    for column, label in MEASURES:
        lines.append(f"- {label}: " + "; ".join(
            f"{describe(r)} {fmt(r['time_loop_s'])} s, {fmt(r[column])}" for r in front[column]))
    lines += ["", "## All runs", ""]
    shown = ["level", "family", "mass", "remedy", "unknowns", "time_step_s", "steps", "time_loop_s",
             "peak_memory_MB", "step_cost_vs_plain_hrz", "force_trend_peak_N_per_m",
             "pressure_trend_peak_Pa", "contact_duration_s", "force_peak_error_percent",
             "duration_error_percent", "force_l2_vs_reference_run_percent", "pressure_peak_error_percent",
             "profile_rms_percent_p0", "force_chatter_percent", "energy_error_percent",
             "force_peak_vs_finest_percent", "pressure_peak_vs_finest_percent"]
    lines.append("| " + " | ".join(shown) + " |")
    lines.append("|" + "---|" * len(shown))
    for r in rows:
        if r.get("status") != "completed":
            lines.append(f"| {r['level']} | {r['family']} | {r['mass']} | {r['remedy']} | "
                         + f"{r.get('status')} |" + " - |" * (len(shown) - 5))
            continue
        lines.append("| " + " | ".join(fmt(r.get(c)) for c in shown) + " |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("program")
    parser.add_argument("output_dir")
    parser.add_argument("--levels", nargs="+", type=int, default=[2, 3, 4, 5, 6])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))
    parser.add_argument("--masses", nargs="+", default=MASSES, choices=MASSES)
    parser.add_argument("--remedies", nargs="+", default=["plain", "damping"], choices=list(REMEDIES))
    parser.add_argument("--end-time", type=float, default=0.9)
    parser.add_argument("--skip-run", action="store_true", help="only collect and draw")
    parser.add_argument("--reuse", action="store_true",
                        help="run only the configurations without a summary.json")
    args = parser.parse_args()
    program, work = os.path.abspath(args.program), os.path.abspath(args.output_dir)
    os.makedirs(work, exist_ok=True)
    configurations = [(level, family, mass, remedy) for level in args.levels
                      for family in args.families for mass in args.masses
                      for remedy in args.remedies]
    start = clock.time()
    for i, configuration in enumerate(configurations):
        if args.skip_run:
            break
        if args.reuse and os.path.exists(os.path.join(work, run_name(*configuration),
                                                      "summary.json")):
            continue
        status = run(program, work, *configuration, args.end_time)
        print(f"[{i + 1}/{len(configurations)}, {clock.time() - start:.0f} s] "
              f"{run_name(*configuration)}: exit {status}", flush=True)
    rows = [collect(work, *configuration) for configuration in configurations]
    add_errors(rows)
    with open(os.path.join(work, "tradeoff.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    front = fronts(rows)
    plot(rows, front, os.path.join(work, "fig_pareto.png"))
    if len(args.levels) == 1:
        plot_remedies(rows, os.path.join(work, "fig_remedies.png"))
    command = "python3 scripts/tradeoff_study.py build/isoimpact OUT " + " ".join(sys.argv[3:])
    write_markdown(rows, front, os.path.join(work, "tradeoff.md"), command.strip())
    print(open(os.path.join(work, "tradeoff.md")).read())
    print(f"{len(configurations)} configurations, {clock.time() - start:.0f} s; "
          f"{work}/tradeoff.csv, tradeoff.md, fig_pareto.png")


if __name__ == "__main__":
    main()
