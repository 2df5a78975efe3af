#!/usr/bin/env python3
"""The shared contact measures of the project (README, doc/results.md) for
one or more run directories (each with history.csv at History interval = 1):

- trend: the 50 ms centred moving average of a signal;
- chatter: RMS over the contact (first to last sample with a positive raw
  force) of (raw - trend), in % of the trend peak;
- force trend peak [N/m], maximal-pressure trend peak [Pa];
- energy error: max over the run of |total_energy - E0| / E0 (the total
  includes the work of the contact damping);
- profile RMS: RMS over |x| < 0.9 a of (consistent pressure - Hertz
  pressure) in % of p0, from the pressure profile at t = 0.375 s (a and p0
  of the analytic profile in the same file); the same for the Gauss-point
  pressure;
- contact duration [s] and time step [s] from summary.json.

usage: python3 scripts/contact_measures.py RUN_DIR [RUN_DIR ...]"""
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from isoimpact_results import hertz_support, moving_average, read_history, read_profile, window_width  # noqa: E402

TREND_WINDOW_S = 0.05


PROFILE_TIME_S = 0.375


def profile_rms(directory):
    """(consistent, Gauss-point) RMS deviation from the Hertz profile over
    |x| < 0.9 a, in % of p0; None if there is no profile at 0.375 s."""
    p = read_profile(directory, PROFILE_TIME_S)
    if p is None:
        return None, None
    a, p0 = hertz_support(p)
    analytic = p["analytic_pressure"]
    mask = np.abs(p["position"]) < 0.9 * a
    rms = lambda c: 100 * float(np.sqrt(np.mean((p[c][mask] - analytic[mask]) ** 2))) / p0  # noqa: E731
    return rms("pressure"), rms("gauss_point_pressure")


def measures(directory):
    history = read_history(directory)
    time = history["time"]
    dt = float(np.median(np.diff(time)))
    width = window_width(TREND_WINDOW_S, dt)
    force = history["contact_force"]
    pressure = history["max_contact_pressure"]
    force_trend = moving_average(force, width)
    pressure_trend = moving_average(pressure, width)
    active = np.flatnonzero(force > 0)
    mask = np.zeros(len(force), dtype=bool)
    if len(active):
        mask[active[0]:active[-1] + 1] = True
    peak = float(np.max(force_trend))
    chatter = float(np.sqrt(np.mean((force - force_trend)[mask] ** 2))) / peak
    total = history["total_energy"]
    with open(os.path.join(directory, "summary.json")) as f:
        summary = json.load(f)
    profile, gauss_profile = profile_rms(directory)
    return {"run": os.path.basename(os.path.normpath(directory)),
            "time_step_s": summary["time_step_s"],
            "force_trend_peak_N_per_m": peak,
            "force_chatter_percent": 100 * chatter,
            "pressure_trend_peak_Pa": float(np.max(pressure_trend)),
            "gauss_pressure_trend_peak_Pa": float(np.max(moving_average(
                history["max_gauss_point_pressure"], width))),
            "profile_rms_percent_p0": profile,
            "gauss_profile_rms_percent_p0": gauss_profile,
            "energy_error_percent": 100 * float(np.max(np.abs(total - total[0])) / total[0]),
            "damping_work_percent": 100 * float(history.get("contact_damping_work", [0])[-1] / total[0]),
            "contact_duration_s": summary.get("contact_duration_s"),
            "wall_time_s": summary.get("wall_time_s")}


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rows = [measures(d) for d in sys.argv[1:]]
    keys = list(rows[0])
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for r in rows:
        print("| " + " | ".join(f"{v:.4g}" if isinstance(v, float) else str(v)
                                for v in r.values()) + " |")


if __name__ == "__main__":
    main()
