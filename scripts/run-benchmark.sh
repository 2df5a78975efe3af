#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the main job: the dynamic Hertz impact
# with FE_Q(2) and HRZ mass (prm/hertz_fea_hrz.prm), or the .prm file given.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
prm="${1:-prm/hertz_fea_hrz.prm}"
./build/isoimpact "$prm"
