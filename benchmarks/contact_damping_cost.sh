#!/usr/bin/env bash
# Per-step cost of the contact damping against plain HRZ (issue 11): the
# benchmark file prm/hertz_fea_hrz.prm (or $1) at one fixed step, 3.5e-4 s
# (the same number of steps for both), no VTU and no profiles, with
# Contact/Damping ratio 0.2 (A) against 0 (B), timed as whole processes
# with farm-bench, run by run in pairs. Quote the median A/B.
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
farm-bench -n "$runs" --timeout 900 --vs "build/isoimpact $work/damping_0.prm" \
  -- build/isoimpact "$work/damping_0.2.prm"
