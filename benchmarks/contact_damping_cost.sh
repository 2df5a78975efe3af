#!/usr/bin/env bash
# Per-step cost of the contact damping against plain HRZ (issue 11): the
# benchmark file prm/hertz_fea_hrz.prm (or $1) at one fixed step, 3.5e-4 s
# (the same number of steps for both), no VTU and no profiles, with
# Contact/Damping ratio 0.2 (A) against 0 (B), run in turn A B A B ...;
# each run's time loop from its summary.json (wall_time_parts_s), the
# ratio A/B taken pair by pair. Quote the median A/B.
# usage: bash benchmarks/contact_damping_cost.sh [PRM] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
prm=${1:-prm/hertz_fea_hrz.prm}
runs=${2:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for xi in 0 0.2; do
  /usr/bin/python3 - "$prm" "$work" "$xi" <<'PY'
import sys
sys.path.insert(0, "tests/scripts")
from testing import edit_prm
prm, work, xi = sys.argv[1:4]
edit_prm(prm, f"{work}/damping_{xi}.prm", {
    "Contact/Damping ratio": xi, "Time integration/Time step": "3.5e-4",
    "Time integration/Allow time step above the stable estimate": "true",
    "Output/VTU interval": "0", "Output/Pressure profile times": "",
    "Output/Directory": f"{work}/out_{xi}"})
PY
done
/usr/bin/python3 - "$work" "$runs" <<'PY'
import json, statistics, subprocess, sys
work, runs = sys.argv[1], int(sys.argv[2])
def loop_time(xi):
    subprocess.run(["build/isoimpact", f"{work}/damping_{xi}.prm"], check=True,
                   stdout=subprocess.DEVNULL)
    with open(f"{work}/out_{xi}/summary.json") as f:
        return json.load(f)["wall_time_parts_s"]["time_loop"]
pairs = [(loop_time("0.2"), loop_time("0")) for _ in range(runs)]
for name, values in (("A (damping 0.2) time loop [s]", [a for a, _ in pairs]),
                     ("B (damping 0) time loop [s]", [b for _, b in pairs]),
                     ("A/B", [a / b for a, b in pairs])):
    print(f"{name}: median {statistics.median(values):.4g}, "
          f"min {min(values):.4g}, max {max(values):.4g}")
PY
