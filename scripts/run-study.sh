#!/usr/bin/env bash
# Sets up (scripts/setup.sh) and runs the Hertz study (scripts/hertz_study.py):
# the six prm/hertz_{fea,iga}_{hrz,rowsum,consistent}.prm runs, figures and
# results table in output/study/. Arguments go to the driver, e.g.
# `bash scripts/run-study.sh --skip-run` to redraw from existing outputs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
/usr/bin/python3 scripts/hertz_study.py "$@"
