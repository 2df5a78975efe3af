"""The filtered peaks of summary.json are the Python filter
(scripts/isoimpact_results.py) applied to history.csv: the peak of the
centred moving average over Output/Filter window of the contact force and
of the maximal contact pressure, and the time of the force's, of the run in
the directory given (written with History interval = 1, so that history.csv
holds every step the program filtered).

Tolerance: relative 1e-9 for the peaks (history.csv is written with 10
significant digits, and the Python filter sums in another order); the time
of the filtered peak force to 1e-9 s (the same sample). The filter must
matter: the filtered peaks are at least 1 % below the raw ones."""
import json
import os
import sys

import numpy as np

from testing import check_close, check_true, report

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "scripts"))
import isoimpact_results  # noqa: E402

directory = sys.argv[1]
summary = json.load(open(os.path.join(directory, "summary.json")))
history = isoimpact_results.read_history(directory)

dt = summary["time_step_s"]
time = history["time"]
check_true(f"history.csv has every step: {len(time)} rows for {summary['steps']} steps",
           len(time) == summary["steps"] + 1)
check_close("history.csv: largest time step [s]", float(np.max(np.diff(time))), dt, 1e-9)
width = isoimpact_results.window_width(summary["filter_window_s"], dt)
check_close("filter width [samples] of filter_window_s", width * dt,
            summary["filter_window_s"], 1e-12)

force = isoimpact_results.moving_average(history["contact_force"], width)
pressure = isoimpact_results.moving_average(history["max_contact_pressure"], width)
check_close("filtered peak contact force [N/m]: summary.json vs Python filter",
            summary["filtered_peak_contact_force_N_per_m"], float(np.max(force)), 1e-9)
check_close("filtered peak contact pressure [Pa]: summary.json vs Python filter",
            summary["filtered_peak_contact_pressure_Pa"], float(np.max(pressure)), 1e-9)
check_close("time of the filtered peak force [s]: summary.json vs Python filter",
            summary["time_of_filtered_peak_force_s"], float(time[np.argmax(force)]), 1e-9,
            relative=False)
check_true("the filter lowers the force peak by more than 1 %% (%.2f -> %.2f N/m)"
           % (summary["peak_contact_force_N_per_m"],
              summary["filtered_peak_contact_force_N_per_m"]),
           summary["filtered_peak_contact_force_N_per_m"]
           < 0.99 * summary["peak_contact_force_N_per_m"])
check_true("the filter lowers the pressure peak by more than 1 %% (%.2f -> %.2f Pa)"
           % (summary["peak_contact_pressure_Pa"], summary["filtered_peak_contact_pressure_Pa"]),
           summary["filtered_peak_contact_pressure_Pa"]
           < 0.99 * summary["peak_contact_pressure_Pa"])
report()
