"""The Hertz impact study: runs a list of .prm files (FEA and IGA with
consistent, row-sum and HRZ mass), then draws the comparison figures against
the analytic reference and writes the results table.

    /usr/bin/python3 scripts/hertz_study.py                 # run all, draw
    /usr/bin/python3 scripts/hertz_study.py --skip-run      # redraw only
    /usr/bin/python3 scripts/hertz_study.py --prm-list a.prm b.prm \
        --output-root /tmp/runs --study-dir /tmp/study

Each run goes to OUTPUT_ROOT/<name of the .prm> (the .prm's own
Output/Directory is replaced in a copy, OUTPUT_ROOT/<name>.prm; the
program's terminal output is in OUTPUT_ROOT/<name>.log). The study
directory receives:

- fig_fea_vs_iga_hrz.png: contact force and maximal pressure against time,
  the runs with HRZ mass (FEA against IGA);
- fig_iga_mass.png: the same for the IGA runs (consistent, row-sum, HRZ);
- fig_pressure_profiles.png: the pressure along the contact surface at the
  profile time nearest the analytic time of peak force, with the Hertz
  profile p0 sqrt(1 - x^2/a^2);
- results_table.md, results_table.csv: one row per run (see doc/output.md),
  oscillation measures as in doc/oscillation.md.

A figure whose runs are not in the list is left out (with a message).
Exit status 1 if a run fails or its outputs are missing."""
import argparse
import csv
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time as clock
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import isoimpact_results  # noqa: E402
import oscillation  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_PRMS = ["prm/hertz_fea_hrz.prm", "prm/hertz_fea_q8_hrz.prm", "prm/hertz_fea_rowsum.prm",
                "prm/hertz_fea_consistent.prm", "prm/hertz_iga_hrz.prm",
                "prm/hertz_iga_rowsum.prm", "prm/hertz_iga_consistent.prm"]
# Windows [s] of the moving average for the sensitivity table.
SENSITIVITY_WINDOWS = (0.005, 0.01, 0.02)
DPI = 100


# ---------------------------------------------------------------------------
# Running
def run_directory(root, prm):
    return os.path.join(root, os.path.splitext(os.path.basename(prm))[0])


def run_one(program, prm, root):
    """Runs one .prm with its output redirected to run_directory(root, prm);
    returns (prm, return code, seconds)."""
    out = run_directory(root, prm)
    text = open(prm).read()
    text, count = re.subn(r"(?m)^(\s*set\s+Directory\s*=).*$",
                          lambda m: m.group(1) + " " + out, text)
    if count != 1:
        raise SystemExit(f"{prm}: expected one 'set Directory' line, found {count}")
    copy = out + ".prm"
    with open(copy, "w") as f:
        f.write(text)
    shutil.rmtree(out, ignore_errors=True)
    start = clock.time()
    with open(out + ".log", "w") as log:
        code = subprocess.call([program, copy], stdout=log, stderr=subprocess.STDOUT,
                               cwd=root)
    seconds = clock.time() - start
    print(f"  {os.path.basename(prm)}: exit {code} after {seconds:.0f} s "
          f"(log {out}.log)", flush=True)
    return prm, code, seconds


def run_all(program, prms, root, jobs):
    os.makedirs(root, exist_ok=True)
    print(f"running {len(prms)} files, {jobs} at a time, into {root}", flush=True)
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        results = list(pool.map(lambda p: run_one(program, p, root), prms))
    return [prm for prm, code, _ in results if code != 0]


# ---------------------------------------------------------------------------
# Reading
def profile_time(path):
    """The time a profile was written: its first comment line ('... at t = X
    s'), else the number in its name."""
    with open(path) as f:
        m = re.search(r"t = ([0-9.eE+-]+)", f.readline())
    if m:
        return float(m.group(1))
    return float(re.search(r"_t([0-9.eE+-]+)\.csv$", path).group(1))


def prm_value(path, name):
    m = re.search(r"(?m)^\s*set\s+" + re.escape(name) + r"\s*=\s*(\S+)", open(path).read())
    return m.group(1) if m else ""


class Run:
    def __init__(self, prm, directory):
        self.prm, self.directory = prm, directory
        self.name = os.path.splitext(os.path.basename(prm))[0]
        self.summary = json.load(open(os.path.join(directory, "summary.json")))
        self.history = isoimpact_results.read_history(directory)
        method = prm_value(os.path.join(directory, "parameters.prm"), "Method") or \
            prm_value(prm, "Method")
        self.method = method.upper()
        element = prm_value(os.path.join(directory, "parameters.prm"), "FEA element") or \
            prm_value(prm, "FEA element")
        if self.method == "FEA":
            self.method = "FEA-Q8" if element == "serendipity" else "FEA-Q9"
        self.mass = self.summary["mass_matrix"]
        self.label = f"{self.method} {self.mass}"
        level = re.search(r"_g(\d+)$", self.name)
        if level:  # a refinement-study file
            self.label += f" (level {level.group(1)})"
        self.analytic = self.summary["analytic"]
        self.dt = oscillation.time_step(self.history["time"])

    def measures(self, window_s=oscillation.DEFAULT_WINDOW_S):
        h = self.history
        return {
            "force": oscillation.oscillation_measures(
                h["time"], h["contact_force"], h["analytic_contact_force"],
                self.analytic["peak_contact_force_N_per_m"], window_s),
            "pressure": oscillation.oscillation_measures(
                h["time"], h["max_contact_pressure"], h["analytic_max_contact_pressure"],
                self.analytic["peak_contact_pressure_Pa"], window_s),
        }

    def smooth(self, column, window_s):
        return isoimpact_results.moving_average(
            self.history[column], isoimpact_results.window_width(window_s, self.dt))


# ---------------------------------------------------------------------------
# Figures
COLOURS = {"FEA-Q9 HRZ": "tab:blue", "FEA-Q9 row-sum": "tab:cyan", "FEA-Q9 consistent": "tab:purple",
           "FEA-Q8 HRZ": "tab:brown",
           "IGA HRZ": "tab:red", "IGA row-sum": "tab:orange", "IGA consistent": "tab:green"}


def colour(run, i):
    return COLOURS.get(run.label, f"C{i}")


def time_figure(runs, title, path, window_s):
    """Force and maximal pressure against time: raw (thin), moving average
    over window_s (thick), analytic (black dashed)."""
    fig, axes = plt.subplots(2, 1, figsize=(10, 8.5), sharex=True)
    law = runs[0].analytic["approach_law"]
    for ax, column, analytic, unit, what in (
            (axes[0], "contact_force", "analytic_contact_force", "N/m", "contact force"),
            (axes[1], "max_contact_pressure", "analytic_max_contact_pressure", "Pa",
             "maximal contact pressure")):
        for i, run in enumerate(runs):
            t = run.history["time"]
            ax.plot(t, run.history[column], color=colour(run, i), lw=0.6, alpha=0.45,
                    label=f"{run.label}, raw")
            ax.plot(t, run.smooth(column, window_s), color=colour(run, i), lw=2.0,
                    label=f"{run.label}, {window_s * 1e3:g} ms moving average")
        ax.plot(runs[0].history["time"], runs[0].history[analytic], "k--", lw=1.8,
                label=f"analytic (quasi-static Hertz, {law})")
        ax.set_ylabel(f"{what} [{unit}]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, ncol=2, loc="upper right")
        # The raw pressure chatters to several times the analytic peak: keep
        # the analytic scale readable, say where the raw curve is cut.
        top = max(float(np.max(run.smooth(column, window_s))) for run in runs)
        top = 1.25 * max(top, float(np.max(runs[0].history[analytic])))
        raw_top = max(float(np.max(run.history[column])) for run in runs)
        if raw_top > 1.6 * top:
            ax.set_ylim(0, 1.6 * top)
            ax.text(0.01, 0.97, f"raw signals clipped (maximum {raw_top:.4g} {unit})",
                    transform=ax.transAxes, va="top", fontsize=8)
        else:
            ax.set_ylim(0, 1.05 * max(raw_top, top))
    axes[1].set_xlabel("time [s]")
    axes[0].set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"  wrote {path}")


def profile_figure(runs, path):
    """Pressure along the contact surface at the profile time nearest the
    analytic time of peak force, with the Hertz profile of the analytic force
    at that time (a = 2 P / (pi p0) from the analytic columns)."""
    n = len(runs)
    cols = min(3, n)
    rows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(5.4 * cols, 5.2 * rows), squeeze=False)
    for ax in axes.flat[n:]:
        ax.axis("off")
    for i, (run, ax) in enumerate(zip(runs, axes.flat)):
        t_peak = run.analytic["time_of_peak_force_s"]
        files = glob.glob(os.path.join(run.directory, "contact_pressure_t*.csv"))
        if not files:
            ax.set_title(f"{run.label}: no pressure profile")
            continue
        chosen = min(files, key=lambda f: abs(profile_time(f) - t_peak))
        t = profile_time(chosen)
        p = isoimpact_results.read_columns(chosen)
        h = run.history
        force = float(np.interp(t, h["time"], h["analytic_contact_force"]))
        p0 = float(np.interp(t, h["time"], h["analytic_max_contact_pressure"]))
        a = 2 * force / (math.pi * p0)
        # The half model has its contact surface on one side of the line of
        # impact: positions are >= 0 (reference configuration).
        x = np.linspace(0, a, 301)
        ax.plot(x, p0 * np.sqrt(np.maximum(0, 1 - (x / a) ** 2)), "k--", lw=1.8,
                label=f"Hertz p0 sqrt(1 - x²/a²), p0 = {p0:.1f} Pa, a = {a:.2f} m")
        for surface, style in ((1, dict(marker="o", ms=6, mfc="none", lw=1.0)),
                               (2, dict(marker="x", ms=4, lw=0.6, ls=":"))):
            s = p["surface"] == surface
            order = np.argsort(p["position"][s])
            ax.plot(p["position"][s][order], p["pressure"][s][order],
                    color=colour(run, i) if surface == 1 else "0.3", **style,
                    label=f"{run.label}, Gauss points of surface {surface}, t = {t:g} s")
        ax.set_title(f"{run.label}: t = {t:g} s (analytic peak at {t_peak:.4g} s)",
                     fontsize=10)
        ax.set_xlabel("position across the line of impact [m]")
        ax.set_ylabel("contact pressure [Pa]")
        top = max([p0] + list(p["pressure"]))
        ax.set_xlim(0, 1.3 * a)
        ax.set_ylim(0, 1.1 * top)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.16))
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    print(f"  wrote {path}")


# ---------------------------------------------------------------------------
# Table
COLUMNS = [  # (csv name, markdown header, format)
    ("configuration", "configuration", "{}"),
    ("unknowns", "unknowns [-]", "{:d}"),
    ("time_step_s", "dt [s]", "{:g}"),
    ("wall_time_s", "wall time [s]", "{:.1f}"),
    ("peak_force_raw_N_per_m", "peak force raw [N/m]", "{:.1f}"),
    ("peak_force_raw_error_percent", "error [%]", "{:+.1f}"),
    ("peak_force_filtered_N_per_m", "peak force filtered [N/m]", "{:.1f}"),
    ("peak_force_filtered_error_percent", "error [%]", "{:+.1f}"),
    ("time_of_filtered_peak_s", "time of filtered peak [s]", "{:.4f}"),
    ("time_of_filtered_peak_error_percent", "error [%]", "{:+.1f}"),
    ("contact_duration_s", "contact duration [s]", "{:.4f}"),
    ("contact_duration_error_percent", "error [%]", "{:+.2f}"),
    ("peak_pressure_raw_Pa", "peak pressure raw [Pa]", "{:.1f}"),
    ("peak_pressure_raw_error_percent", "error [%]", "{:+.0f}"),
    ("peak_pressure_filtered_Pa", "peak pressure filtered [Pa]", "{:.1f}"),
    ("peak_pressure_filtered_error_percent", "error [%]", "{:+.0f}"),
    ("force_oscillation_vs_analytic_percent", "force osc. vs analytic [% P_max]", "{:.1f}"),
    ("force_oscillation_vs_moving_average_percent", "force osc. vs own MA [% P_max]",
     "{:.1f}"),
    ("pressure_oscillation_vs_analytic_percent", "pressure osc. vs analytic [% p0]",
     "{:.0f}"),
    ("pressure_oscillation_vs_moving_average_percent", "pressure osc. vs own MA [% p0]",
     "{:.0f}"),
    ("max_energy_error_percent", "energy error [%]", "{:.2f}"),
]


# (table column, summary.json key, its error column, key in relative_error)
SUMMARY_VALUES = [
    ("peak_force_raw_N_per_m", "peak_contact_force_N_per_m",
     "peak_force_raw_error_percent", "peak_contact_force"),
    ("peak_force_filtered_N_per_m", "filtered_peak_contact_force_N_per_m",
     "peak_force_filtered_error_percent", "filtered_peak_contact_force"),
    ("time_of_filtered_peak_s", "time_of_filtered_peak_force_s",
     "time_of_filtered_peak_error_percent", "time_of_filtered_peak_force"),
    ("contact_duration_s", "contact_duration_s",
     "contact_duration_error_percent", "contact_duration"),
    ("peak_pressure_raw_Pa", "peak_contact_pressure_Pa",
     "peak_pressure_raw_error_percent", "peak_contact_pressure"),
    ("peak_pressure_filtered_Pa", "filtered_peak_contact_pressure_Pa",
     "peak_pressure_filtered_error_percent", "filtered_peak_contact_pressure"),
]


def table_row(run, window_s):
    s, m = run.summary, run.measures(window_s)
    row = {"configuration": run.label, "unknowns": int(s["unknowns"]),
           "time_step_s": s["time_step_s"], "wall_time_s": s["wall_time_s"],
           "max_energy_error_percent": 100 * s["max_energy_error"]}
    for column, key, error_column, error_key in SUMMARY_VALUES:
        row[column] = s[key]
        # None: no value to compare (the contact lasts at the end time).
        error = s["relative_error"][error_key]
        row[error_column] = None if error is None else 100 * error
    for signal in ("force", "pressure"):
        row[f"{signal}_oscillation_vs_analytic_percent"] = 100 * m[signal]["total"]
        row[f"{signal}_oscillation_vs_moving_average_percent"] = 100 * m[signal]["chatter"]
    return row


def markdown_table(headers, rows):
    lines = ["| " + " | ".join(headers) + " |",
             "|" + "|".join("---" for _ in headers) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def write_tables(runs, study, window_s, jobs_note):
    rows = [table_row(run, window_s) for run in runs]
    with open(os.path.join(study, "results_table.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow([c[0] for c in COLUMNS])
        for r in rows:
            writer.writerow([r[c[0]] if isinstance(r[c[0]], str) else repr(r[c[0]])
                             for c in COLUMNS])
    a = runs[0].analytic
    text = [
        "# Dynamic Hertz impact: FEA and IGA against the analytic reference",
        "",
        f"Analytic reference (quasi-static Hertz impact, {a['approach_law']}, "
        "doc/hertz-reference.md): "
        f"peak force P_max = {a['peak_contact_force_N_per_m']:.2f} N/m at "
        f"{a['time_of_peak_force_s']:.4f} s, contact duration "
        f"{a['contact_duration_s']:.4f} s, peak pressure p0 = "
        f"{a['peak_contact_pressure_Pa']:.2f} Pa. Errors are (value - analytic) / "
        "analytic. Filtered: centred moving average over the program's "
        "Output/Filter window (summary.json). Oscillation measures "
        "(doc/oscillation.md): RMS over the contact interval of the raw signal "
        f"minus the analytic curve, or minus its own {window_s * 1e3:g} ms centred "
        "moving average (MA), as a percentage of the analytic peak. "
        f"Wall time: {jobs_note}.",
        "",
        markdown_table([c[1] for c in COLUMNS],
                       [["-" if r[c[0]] is None else c[2].format(r[c[0]])
                         for c in COLUMNS] for r in rows]),
        "",
        "## Oscillation against the own moving average, by window",
        "",
        "The chatter measure for windows of "
        + ", ".join(f"{w * 1e3:g}" for w in SENSITIVITY_WINDOWS)
        + " ms (force [% P_max] / pressure [% p0]); the window actually spans "
        "2 floor(round(w / dt) / 2) + 1 samples.",
        "",
    ]
    sens_rows = []
    for run in runs:
        cells = [run.label]
        for w in SENSITIVITY_WINDOWS:
            m = run.measures(w)
            cells.append(f"{100 * m['force']['chatter']:.2f} / "
                         f"{100 * m['pressure']['chatter']:.1f}")
        sens_rows.append(cells)
    text.append(markdown_table(
        ["configuration"] + [f"window {w * 1e3:g} ms [%] / [%]" for w in SENSITIVITY_WINDOWS],
        sens_rows))
    text += ["", "## Where the oscillation is: spectrum of (raw - analytic) over the contact",
             "", "Periodogram with a Hann window (oscillation.spectrum): the largest peak "
             "above 20 Hz and the share of the power above 100 Hz (below it: the slow "
             "model error and any oscillation slower than 100 Hz).", ""]
    spectra = []
    for run in runs:
        h = run.history
        cells = [run.label]
        for column, analytic in (("contact_force", "analytic_contact_force"),
                                 ("max_contact_pressure", "analytic_max_contact_pressure")):
            sp = oscillation.spectrum(h["time"], h[column], h[analytic])
            cells += [f"{sp['dominant_hz']:.0f}", f"{100 * sp['share_above']:.0f}"]
        spectra.append(cells)
    text.append(markdown_table(
        ["configuration", "force: peak [Hz]", "force: power above 100 Hz [%]",
         "pressure: peak [Hz]", "pressure: power above 100 Hz [%]"], spectra))
    text.append("")
    path = os.path.join(study, "results_table.md")
    open(path, "w").write("\n".join(text))
    print(f"  wrote {path} and results_table.csv")
    return rows


# ---------------------------------------------------------------------------
def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--prm-list", nargs="+", default=DEFAULT_PRMS, metavar="PRM",
                        help="parameter files, in table order (default: the six "
                             "prm/hertz_{fea,iga}_{hrz,rowsum,consistent}.prm)")
    parser.add_argument("--skip-run", action="store_true",
                        help="do not run: redraw from the existing outputs")
    parser.add_argument("--output-root", default=os.path.join(REPO, "output"),
                        help="where the runs go, one directory per .prm named "
                             "after it (default: output/)")
    parser.add_argument("--study-dir", default=None,
                        help="figures and tables (default: OUTPUT_ROOT/study)")
    parser.add_argument("--program", default=os.path.join(REPO, "build", "isoimpact"))
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time (default 2)")
    parser.add_argument("--window", type=float, default=oscillation.DEFAULT_WINDOW_S,
                        help="moving-average window [s] of the chatter measure and "
                             "the smoothed curves (default 0.01)")
    args = parser.parse_args()
    root = os.path.abspath(args.output_root)
    study = os.path.abspath(args.study_dir or os.path.join(root, "study"))
    prms = [os.path.abspath(p) for p in args.prm_list]
    failed = []
    if not args.skip_run:
        failed = run_all(os.path.abspath(args.program), prms, root, args.jobs)
    runs = []
    for prm in prms:
        directory = run_directory(root, prm)
        try:
            runs.append(Run(prm, directory))
        except (OSError, KeyError, ValueError, IndexError) as error:
            print(f"  {os.path.basename(prm)}: no usable output in {directory} ({error})")
            failed.append(prm)
    if not runs:
        print("nothing to draw")
        return 1
    os.makedirs(study, exist_ok=True)
    print(f"drawing into {study}")
    groups = (
        ("fig_fea_vs_iga_hrz.png", "FEA against IGA, HRZ mass",
         [r for r in runs if r.mass == "HRZ"]),
        ("fig_iga_mass.png", "IGA: consistent, row-sum and HRZ mass",
         [r for r in runs if r.method == "IGA"]),
        ("fig_fea_q8_vs_q9.png", "FEA with the study's Q8 element and with Q9, HRZ mass",
         [r for r in runs if r.method.startswith("FEA") and r.mass == "HRZ"]),
    )
    for name, title, group in groups:
        if group:
            time_figure(group, title, os.path.join(study, name), args.window)
        else:
            print(f"  {name} left out: none of its runs in the list")
    profile_figure(runs, os.path.join(study, "fig_pressure_profiles.png"))
    note = (f"as measured by the program, {args.jobs} runs at a time on a shared machine"
            if not args.skip_run else "as measured by the program (see summary.json)")
    write_tables(runs, study, args.window, note)
    if failed:
        print("failed or missing: " + ", ".join(os.path.basename(p) for p in failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
