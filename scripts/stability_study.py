#!/usr/bin/env python3
"""The stability study of doc/stability.md: for each scene, the guaranteed
stable-step bound and the power estimate the program prints, the true stable
step found by search (the largest step at which the run completes without the
stability monitor stopping it), and the outcome at the automatic step.

usage: python3 scripts/stability_study.py PROGRAM OUTPUT_DIR [--quick]
Writes OUTPUT_DIR/stability.csv and OUTPUT_DIR/stability.md (the tables of
doc/stability.md). Runs one program at a time."""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "tests", "scripts"))
from testing import edit_prm  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
BASE = os.path.join(ROOT, "tests", "prm", "hertz_fea_hrz_coarse.prm")
GRID = 1.05        # upward scan of the step, ratio between runs
RESOLUTION = 1.015  # bisection until hi / lo <= RESOLUTION
START = 0.6        # the search starts at START * bound
COLUMNS = ["group", "case", "exit_code", "status", "unknowns",
           "element_bound_s", "gershgorin_bound_s", "bound_s", "estimate_s",
           "true_limit_s", "bound_over_true", "estimate_over_true",
           "blowup_limit_s", "search_runs", "search_end_time_s", "time_step_s", "steps",
           "wall_time_s", "max_energy_error_rel", "max_penetration_m",
           "filtered_peak_N_per_m", "filtered_peak_error_rel",
           "contact_duration_s", "stop_reason"]


def run(program, work, name, edits):
    """Runs the program on BASE with edits; returns (exit code, summary or
    None, output). The output folder is emptied first: no stale summary."""
    folder = os.path.join(work, name)
    prm = os.path.join(work, name + ".prm")
    shutil.rmtree(folder, ignore_errors=True)
    edits = dict(edits)
    edits.setdefault("Output/Directory", folder)
    edits.setdefault("Output/VTU interval", "0")
    edits.setdefault("Output/History interval", "10")
    edits.setdefault("Output/Pressure profile times", "")
    edits.setdefault("Output/Progress interval", "100")
    edit_prm(BASE, prm, edits)
    result = subprocess.run([program, prm], capture_output=True, text=True)
    summary = None
    path = os.path.join(folder, "summary.json")
    if os.path.exists(path):
        with open(path) as f:
            summary = json.load(f)
    return result.returncode, summary, result.stdout + result.stderr


def completes(program, work, name, edits, dt):
    e = dict(edits)
    e["Time integration/Time step"] = repr(dt)
    e["Time integration/Allow time step above the stable estimate"] = "true"
    code, summary, _ = run(program, work, name + "_search", e)
    return code == 0 and summary is not None and summary["status"] == "completed"


def true_limit(program, work, name, edits, start):
    """The first step that fails on the grid start * GRID^k scanned upward
    (downward by 1.25 if start fails), then bisection between the last step
    that completes and the first that fails. Returns (limit, runs)."""
    ok = lambda dt: completes(program, work, name, edits, dt)  # noqa: E731
    runs = 1
    if ok(start):
        lo, hi = start, start * GRID
        while ok(hi):
            runs += 1
            lo, hi = hi, hi * GRID
            if hi > 20 * start:
                return math.inf, runs
        runs += 1
    else:
        lo, hi = start / 1.25, start
        while not ok(lo):
            runs += 1
            lo, hi = lo / 1.25, lo
            if lo < start / 100:
                return math.nan, runs
        runs += 1
    while hi / lo > RESOLUTION:
        mid = math.sqrt(lo * hi)
        runs += 1
        if ok(mid):
            lo = mid
        else:
            hi = mid
    return lo, runs


def cases(quick):
    """(group, case, edits, search): search the true limit or not."""
    elements = [("FEA Q9", {}),
                ("FEA Q8", {"Discretization/FEA element": "serendipity"}),
                ("IGA p2", {"Discretization/Method": "iga"}),
                ("IGA p3", {"Discretization/Method": "iga",
                            "Discretization/Degree": "3"})]
    schemes = ["HRZ", "row-sum", "consistent"]
    table = []
    for element, e1 in elements[::2] if quick else elements:
        for scheme in schemes[:1] if quick else schemes:
            e = dict(e1, **{"Mass matrix/Scheme": scheme})
            table.append(("element and mass, level 3 (coarse test mesh)",
                          f"{element}, {scheme}", e, True))
    if not quick:
        for element, e1 in elements:
            e = dict(e1, **{"Discretization/Global refinements": "4"})
            table.append(("element, HRZ, level 4 (benchmark mesh)",
                          f"{element}, HRZ", e, True))
    for penalty in ["1e3", "1e5", "1e7"] if quick else \
            [f"1e{k}" for k in range(2, 10)]:
        table.append(("penalty, FEA Q9 HRZ, auto", f"eps_N = {penalty} Pa/m",
                      {"Contact/Penalty": penalty}, False))
    for nu in ["0.3", "0.49"] if quick else ["0", "0.3", "0.45", "0.49"]:
        table.append(("Poisson's ratio, FEA Q9 HRZ, auto", f"nu = {nu}",
                      {"Body 1/Material/Poisson's ratio": nu,
                       "Body 2/Material/Poisson's ratio": nu}, False))
    for speed in [0.1, 20] if quick else [0.01, 0.1, 0.5, 2, 5, 9, 10, 20]:
        # the Gerl-Zippelius reference exists for closing speeds below 19.24 m/s
        reference = "Gerl-Zippelius" if 2 * speed < 19.2 else "none"
        table.append(("impact speed, FEA Q9 HRZ, auto", f"{speed:g} m/s each",
                      {"Body 1/Initial velocity": f"0, {-speed:g}",
                       "Body 2/Initial velocity": f"0, {speed:g}",
                       "Output/Analytic reference": reference}, False))
    for level in ["0"] if quick else ["0", "1"]:
        for element, e1 in elements[::2]:
            table.append(("coarsest meshes, HRZ, auto", f"{element}, level {level}",
                          dict(e1, **{"Discretization/Global refinements": level}),
                          False))
    for degree in [] if quick else ["2", "3", "4"]:
        table.append(("IGA degree, HRZ, level 3, auto", f"p = {degree}",
                      {"Discretization/Method": "iga",
                       "Discretization/Degree": degree}, False))
    # The contact activation margin: the energy pump of penalty contact
    # against the safety factor, with the linearised springs (margin 1) and
    # the program's default margin 2.
    for level in ["3"] if quick else ["3", "4"]:
        for margin in ["1", "2"]:
            for factor in ["0.7", "1"] if quick else ["0.5", "0.7", "0.8", "0.85", "0.9", "1"]:
                table.append((f"contact activation margin {margin}, FEA Q9 HRZ, "
                              f"level {level}, auto", f"safety factor {factor}",
                              {"Discretization/Global refinements": level,
                               "Time integration/Contact activation margin": margin,
                               "Time integration/Time step safety factor": factor,
                               "Time integration/Energy growth tolerance": "1"},
                              False))
    channel = {"Obstacle/Type": "channel", "Obstacle/Point": "0, 0",
               "Obstacle/Normal": "0, 1", "Obstacle/Opposite point": "0, 10",
               "Body 1/Shape": "full disk", "Body 1/Center": "0, 5",
               "Body 1/Symmetry cut": "false",
               "Output/Analytic reference": "none",
               "Time integration/End time": "4" if quick else "18"}
    for step in ["auto", "5e-4", "2.5e-4"]:
        table.append(("channel: full disk (R 4 m, level 3) between planes "
                      f"y = 0 and y = 10 m, 2 m/s, {channel['Time integration/End time']} s",
                      f"time step {step}",
                      dict(channel, **{"Time integration/Time step": step}), False))
    return table


def row_of(group, label, code, summary, text):
    row = {"group": group, "case": label, "exit_code": code}
    if summary is None:
        row["stop_reason"] = text.strip().splitlines()[-1] if text.strip() else ""
        return row
    error = summary.get("relative_error", {})
    row.update({
        "status": summary["status"], "unknowns": summary["unknowns"],
        "element_bound_s": summary["stable_time_step_element_bound_s"],
        "gershgorin_bound_s": summary["stable_time_step_gershgorin_bound_s"],
        "bound_s": summary["stable_time_step_bound_s"],
        "estimate_s": summary["stable_time_step_estimate_s"],
        "time_step_s": summary["time_step_s"], "steps": summary["steps"],
        "wall_time_s": summary["wall_time_s"],
        "max_energy_error_rel": summary.get("max_energy_error"),
        "max_penetration_m": summary.get("max_penetration_m"),
        "filtered_peak_N_per_m": summary.get("filtered_peak_contact_force_N_per_m"),
        "filtered_peak_error_rel": error.get("filtered_peak_contact_force"),
        "contact_duration_s": summary.get("contact_duration_s"),
        "stop_reason": summary.get("stop_reason", "")})
    return row


def fmt(value, spec="{:.3g}"):
    if value is None or value == "":
        return ""
    return spec.format(value) if isinstance(value, float) else str(value)


def write_markdown(path, rows):
    """One table per group; the limit columns only where they were searched."""
    with open(path, "w") as f:
        group = None
        for r in rows:
            search = any("true_limit_s" in x for x in rows if x["group"] == r["group"])
            if r["group"] != group:
                group = r["group"]
                head = ["case", "exit", "status", "unknowns", "element bound [s]",
                        "Gershgorin bound [s]", "bound [s]", "estimate [s]"]
                head += ["true limit [s]", "bound / true", "estimate / true",
                         "limit at 100 % energy growth [s]"] if search else []
                head += ["step [s]",
                         "steps", "max energy error", "max penetration [m]",
                         "filtered peak [N/m]", "peak error", "wall [s]"]
                f.write(f"\n### {group}\n\n| " + " | ".join(head) + " |\n|"
                        + "---|" * len(head) + "\n")
            cells = [r["case"], r["exit_code"], r.get("status", "no output"),
                     r.get("unknowns"), fmt(r.get("element_bound_s")),
                     fmt(r.get("gershgorin_bound_s")), fmt(r.get("bound_s")),
                     fmt(r.get("estimate_s"))]
            if search:
                cells += [fmt(r.get("true_limit_s")),
                          fmt(r.get("bound_over_true"), "{:.2f}"),
                          fmt(r.get("estimate_over_true"), "{:.2f}"),
                          fmt(r.get("blowup_limit_s"))]
            cells += [fmt(r.get("time_step_s")), r.get("steps"),
                      fmt(r.get("max_energy_error_rel"), "{:.2%}"),
                      fmt(r.get("max_penetration_m")),
                      fmt(r.get("filtered_peak_N_per_m"), "{:.1f}"),
                      fmt(r.get("filtered_peak_error_rel"), "{:+.1%}"),
                      fmt(r.get("wall_time_s"), "{:.2f}")]
            f.write("| " + " | ".join("" if c is None else str(c) for c in cells)
                    + " |\n")
        for r in rows:
            if r.get("status") != "completed":
                f.write(f"\n- {r['group']} / {r['case']}: exit {r['exit_code']}: "
                        f"{r.get('stop_reason', '')}\n")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    program, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    quick = "--quick" in sys.argv
    os.makedirs(work, exist_ok=True)
    start = time.time()
    rows = []
    for group, label, edits, search in cases(quick):
        name = "".join(c if c.isalnum() else "_" for c in group[:12] + "_" + label)
        auto = dict(edits)
        auto.setdefault("Time integration/Time step", "auto")
        code, summary, text = run(program, work, name, auto)
        row = row_of(group, label, code, summary, text)
        if search and summary is not None:
            bound = summary["stable_time_step_bound_s"]
            end = "0.4" if edits.get("Mass matrix/Scheme") == "consistent" else "0.9"
            edits = dict(edits, **{"Time integration/End time": end})
            limit, runs = true_limit(program, work, name, edits, START * bound)
            row.update({"true_limit_s": limit, "bound_over_true": bound / limit,
                        "estimate_over_true":
                            summary["stable_time_step_estimate_s"] / limit,
                        "search_runs": runs, "search_end_time_s": float(end)})
            if "level 3" in group:  # the limit with 100 % energy growth allowed
                tolerant = dict(edits, **{"Time integration/Energy growth tolerance": "1"})
                row["blowup_limit_s"], more = true_limit(program, work, name, tolerant,
                                                         START * bound)
                row["search_runs"] += more
        print(f"[{time.time() - start:6.0f} s] " + ", ".join(
            f"{k}={fmt(v)}" for k, v in row.items() if k != "stop_reason"), flush=True)
        rows.append(row)
    with open(os.path.join(work, "stability.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    write_markdown(os.path.join(work, "stability.md"), rows)
    print(f"{len(rows)} cases in {time.time() - start:.0f} s: "
          f"{os.path.join(work, 'stability.csv')}, stability.md")


if __name__ == "__main__":
    main()
