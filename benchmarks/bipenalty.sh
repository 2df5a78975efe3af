#!/usr/bin/env bash
# The bipenalty (Contact/Bipenalty, issue 11) on the level-4 benchmark files
# prm/hertz_fea_hrz.prm, prm/hertz_fea_q8_hrz.prm and prm/hertz_iga_hrz.prm,
# each without it, with it (momentum switching) and with velocity switching,
# undamped, at the files' step 5e-4 s (the same
# step, so the time loop's cost per step compares), History interval 1, no
# VTU, the pressure profile at 0.375 s. Prints a markdown table: chatter,
# force trend peak, max-pressure trend peak, profile RMS, energy balance
# error, stable step bound, time loop and cost per step (summary.json
# wall_time_parts_s.time_loop / steps), and the bipenalty's energy terms in
# % of the input energy; writes OUTPUT_DIR/bipenalty.csv. Nine runs, one
# at a time (minutes each on a loaded 2-core machine).
# usage: bash benchmarks/bipenalty.sh [OUTPUT_DIR] [PROGRAM]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-output/bipenalty}
program=${2:-build/isoimpact}
exec /usr/bin/python3 scripts/remedy_scenes.py "$program" "$out" --bipenalty
