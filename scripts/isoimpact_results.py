"""Reading the program's results, for the study scripts and the tests: the
CSV outputs (history.csv, contact_pressure_t*.csv) and the moving average
of the summary's filtered peaks.

    sys.path.insert(0, "<source tree>/scripts")
    import isoimpact_results
    history = isoimpact_results.read_history(run_directory)
    smooth = isoimpact_results.moving_average(
        history["contact_force"], isoimpact_results.window_width(0.01, 5e-4))
"""
import glob
import os

import numpy as np


def read_columns(path):
    """A CSV output of the program as a dict of numpy arrays by column name
    (lines starting with '#' and blank lines skipped; a file without rows
    gives empty columns)."""
    with open(path) as f:
        rows = [line for line in f if line.strip() and not line.startswith("#")]
    names = rows[0].strip().split(",")
    data = np.array([[float(v) for v in row.split(",")] for row in rows[1:]])
    data = data.reshape(-1, len(names))
    return {name: data[:, i] for i, name in enumerate(names)}


def read_history(directory):
    """history.csv of the run in directory (see read_columns)."""
    return read_columns(os.path.join(directory, "history.csv"))


def window_width(window_s, dt):
    """The program's width in samples of the moving average over window_s
    (Output/Filter window): max(1, round(window / dt)); the average then
    spans 2 * (width // 2) + 1 samples."""
    return max(1, int(round(window_s / dt)))


def moving_average(signal, width):
    """Centred moving average over 2 * (width // 2) + 1 samples, the window
    cut (and the mean taken over the samples present) at the ends of the
    signal, as isoimpact::moving_average (source/scene/run_summary.cc)."""
    signal = np.asarray(signal, dtype=float)
    n, half = len(signal), width // 2
    cumulative = np.concatenate(([0.0], np.cumsum(signal)))
    index = np.arange(n)
    lo = np.maximum(0, index - half)
    hi = np.minimum(n, index + half + 1)
    return (cumulative[hi] - cumulative[lo]) / (hi - lo)


def read_profile(directory, time_s):
    """The pressure profile (contact_pressure_t*.csv) written nearest to
    time_s, sorted by position; None if there is none or it has no point
    with an analytic pressure (the contact open at that step)."""
    files = glob.glob(os.path.join(directory, "contact_pressure_t*.csv"))
    if not files:
        return None
    path = min(files, key=lambda f: abs(float(os.path.basename(f)[18:-4]) - time_s))
    profile = read_columns(path)
    if len(profile["position"]) == 0 or not np.any(profile["analytic_pressure"] > 0):
        return None
    order = np.argsort(profile["position"])
    return {k: v[order] for k, v in profile.items()}


def hertz_support(profile):
    """(a, p0) of the analytic profile p0 sqrt(1 - x^2/a^2) in a profile,
    a from its outermost point with a positive analytic pressure."""
    analytic = profile["analytic_pressure"]
    p0 = float(np.max(analytic))
    k = np.argmax(np.where(analytic > 0, np.abs(profile["position"]), -1))
    return abs(profile["position"][k]) / np.sqrt(1 - (analytic[k] / p0) ** 2), p0
