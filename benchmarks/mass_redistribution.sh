#!/usr/bin/env bash
# The mass redistribution remedy (Contact/Mass redistribution, issue 11) on
# the level-4 benchmark files prm/hertz_fea_hrz.prm, prm/hertz_fea_q8_hrz.prm
# and prm/hertz_iga_hrz.prm at their step dt = 5e-4 s, plain HRZ (B) and
# with redistribution (A), no VTU, a pressure profile at 0.375 s. Prints
# the shared measures (scripts/contact_measures.py: force trend peak,
# chatter, max-pressure trend peak, profile RMS, energy error), the boundary
# solve's work from summary.json and the cost per step as the ratio A/B of
# the time-loop wall times (summary.json wall_time_parts_s.time_loop; same
# step, same number of steps). Runs one at a time.
# usage: bash benchmarks/mass_redistribution.sh [WORKDIR] [PENALTY]
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-$(mktemp -d)}
penalty=${2:-1e5}
mkdir -p "$work"
/usr/bin/python3 - "$work" "$penalty" <<'PY'
import json, os, subprocess, sys
sys.path.insert(0, "tests/scripts")
sys.path.insert(0, "scripts")
from testing import edit_prm
from contact_measures import measures
work, penalty = sys.argv[1:3]
files = {"FEA Q9": "prm/hertz_fea_hrz.prm", "FEA Q8": "prm/hertz_fea_q8_hrz.prm",
         "IGA p2": "prm/hertz_iga_hrz.prm"}
rows = []
for family, prm in files.items():
    loop = {}
    for remedy in ["plain", "redistribution"]:
        name = f"{family.replace(' ', '_')}_{remedy}_{penalty}"
        folder = os.path.join(work, name)
        edit_prm(prm, folder + ".prm", {
            "Contact/Mass redistribution": "true" if remedy != "plain" else "false",
            "Contact/Penalty": penalty,
            "Time integration/Time step": "5e-4",
            "Time integration/Allow time step above the stable estimate": "true",
            "Output/VTU interval": "0", "Output/Pressure profile times": "0.375",
            "Output/Progress interval": "100", "Output/Directory": folder})
        run = subprocess.run(["build/isoimpact", folder + ".prm"], capture_output=True, text=True)
        row = {"family": family, "remedy": remedy, "exit": run.returncode}
        if run.returncode == 0:
            row.update(measures(folder))
            with open(os.path.join(folder, "summary.json")) as f:
                s = json.load(f)
            loop[remedy] = s["wall_time_parts_s"]["time_loop"]
            row["time_loop_s"] = loop[remedy]
            row["bound_s"] = s["stable_time_step_bound_s"]
            b = s.get("boundary_solve")
            if b:
                row["evaluations_per_step"] = b["contact_evaluations_per_step"]
                row["factorizations_per_step"] = b["factorizations_per_step"]
                row["max_evaluations"] = b["max_contact_evaluations_per_step"]
        else:
            row["error"] = run.stderr.strip()[-300:]
        if remedy != "plain" and "plain" in loop and remedy in loop:
            row["cost_vs_plain"] = loop[remedy] / loop["plain"]
        rows.append(row)
        print(json.dumps(row), flush=True)
keys = ["family", "remedy", "exit", "force_chatter_percent", "force_trend_peak_N_per_m",
        "pressure_trend_peak_Pa", "profile_rms_percent_p0", "energy_error_percent",
        "bound_s", "evaluations_per_step", "factorizations_per_step", "max_evaluations",
        "time_loop_s", "cost_vs_plain"]
print("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys))
for r in rows:
    print("| " + " | ".join(f"{r[k]:.4g}" if isinstance(r.get(k), float) else str(r.get(k, ""))
                            for k in keys) + " |")
PY
