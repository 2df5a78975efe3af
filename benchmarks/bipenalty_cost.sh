#!/usr/bin/env bash
# Time-loop cost per step of the bipenalty (Contact/Bipenalty, momentum
# switching) against plain, on the level-4 benchmark files at their step
# 5e-4 s (the same steps for both), History interval 1, no VTU: RUNS pairs
# run alternately (plain, bipenalty, plain, ...) so that a drifting machine
# load hits both; per pair the ratio of summary.json's
# wall_time_parts_s.time_loop; prints the medians of each and of the ratio.
# usage: bash benchmarks/bipenalty_cost.sh [RUNS] [PROGRAM]
set -euo pipefail
cd "$(dirname "$0")/.."
exec /usr/bin/python3 - "${1:-5}" "${2:-build/isoimpact}" <<'PY'
import json, os, statistics, subprocess, sys, tempfile
sys.path.insert(0, "tests/scripts")
from testing import edit_prm
runs, program = int(sys.argv[1]), sys.argv[2]
work = tempfile.mkdtemp()
for label, base in [("FEA Q9", "prm/hertz_fea_hrz.prm"), ("FEA Q8", "prm/hertz_fea_q8_hrz.prm"),
                    ("IGA p2", "prm/hertz_iga_hrz.prm")]:
    loops = {"plain": [], "bipenalty": []}
    for k in range(runs):
        for variant in loops:
            folder = os.path.join(work, f"{variant}_{k}")
            prm = edit_prm(base, folder + ".prm", {
                "Contact/Bipenalty": str(variant == "bipenalty").lower(),
                "Time integration/Time step": "5e-4",
                "Time integration/Allow time step above the stable estimate": "true",
                "Output/Directory": folder, "Output/VTU interval": "0",
                "Output/History interval": "1", "Output/Pressure profile times": ""})
            subprocess.run([program, prm], capture_output=True, check=True)
            with open(os.path.join(folder, "summary.json")) as f:
                s = json.load(f)
            loops[variant].append(s["wall_time_parts_s"]["time_loop"] / s["steps"])
    ratios = [b / a for a, b in zip(loops["plain"], loops["bipenalty"])]
    print(f"{label}: time loop per step plain {1e3 * statistics.median(loops['plain']):.3f} ms, "
          f"bipenalty {1e3 * statistics.median(loops['bipenalty']):.3f} ms (medians of {runs}); "
          f"ratio median {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f})",
          flush=True)
PY
