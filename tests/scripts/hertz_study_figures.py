"""The study driver (scripts/hertz_study.py) on the coarse test scenes: runs
them (2 at a time) into WORKDIR, checks that the three figures exist and are
real PNG images (over 10 kB), that the table has one row per scene with
finite numbers and the right configuration names, and that --skip-run
redraws from the same outputs.

Arguments: program, hertz_study.py, WORKDIR, then the .prm files."""
import csv
import math
import os
import shutil
import subprocess
import sys

from testing import check_close, check_true, report

program, driver, workdir, prms = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
shutil.rmtree(workdir, ignore_errors=True)
study = os.path.join(workdir, "study")
command = [sys.executable, driver, "--program", program, "--output-root", workdir,
           "--study-dir", study, "--jobs", "2", "--prm-list"] + prms
run = subprocess.run(command, capture_output=True, text=True)
print(run.stdout[-3000:], run.stderr[-3000:])
check_true("driver exits with 0", run.returncode == 0)

figures = ["fig_fea_vs_iga_hrz.png", "fig_iga_mass.png", "fig_pressure_profiles.png"]


def check_figures():
    for name in figures:
        path = os.path.join(study, name)
        size = os.path.getsize(path) if os.path.exists(path) else 0
        magic = open(path, "rb").read(8) if size else b""
        check_true(f"{name}: PNG of {size} bytes (> 10 kB)",
                   size > 10000 and magic == b"\x89PNG\r\n\x1a\n")


check_figures()
rows = list(csv.DictReader(open(os.path.join(study, "results_table.csv"))))
check_true(f"one table row per scene ({len(rows)} for {len(prms)})", len(rows) == len(prms))
labels = sorted(r["configuration"] for r in rows)
check_true(f"configurations {labels}",
           labels == sorted(["FEA-Q9 HRZ", "IGA consistent", "IGA HRZ", "IGA row-sum"]))
numbers = [(r["configuration"], k, float(v)) for r in rows for k, v in r.items()
           if k != "configuration"]
bad = [(c, k, v) for c, k, v in numbers if not math.isfinite(v)]
check_true(f"all {len(numbers)} numbers finite {bad}", not bad)
for r in rows:
    # Loose sanity bounds, not accuracy checks (hertz_benchmark.py does those).
    check_close(f"{r['configuration']}: contact duration [s]",
                float(r["contact_duration_s"]), 0.7491, 0.15)
    measures = [float(r[k]) for k in r if "oscillation" in k]
    check_true(f"{r['configuration']}: the 4 oscillation measures positive {measures}",
               len(measures) == 4 and min(measures) > 0)
markdown = open(os.path.join(study, "results_table.md")).read()
sections = markdown.split("\n## ")
check_true(f"results_table.md: a main table with units and one row per scene, "
           f"{len(sections) - 1} further sections with one row per scene",
           "peak force raw [N/m]" in sections[0]
           and all(sum(line.startswith(("| FEA", "| IGA")) for line in section.splitlines())
                   == len(prms) for section in sections))

# Redraw only: the figures come back from the existing outputs.
for name in figures:
    os.remove(os.path.join(study, name))
redraw = subprocess.run(command + ["--skip-run"], capture_output=True, text=True)
print(redraw.stdout[-1500:], redraw.stderr[-1500:])
check_true("--skip-run exits with 0 and runs nothing",
           redraw.returncode == 0 and "running" not in redraw.stdout)
check_figures()
report()
