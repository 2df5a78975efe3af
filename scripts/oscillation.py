"""Oscillation measures of a contact signal (force or maximal pressure), as
defined in doc/oscillation.md.

For a raw signal s(t) sampled at a uniform step, an analytic reference r(t)
and the analytic peak r_max:

- total deviation:  RMS over the contact interval of (s - r), over r_max;
- chatter:          RMS over the contact interval of (s - MA_w[s]), over
                    r_max, with MA_w the centred moving average over a window
                    of w seconds (isoimpact_results.moving_average, the
                    filter of the program's filtered peaks, cut at the ends
                    of the record).

The contact interval runs from the first to the last sample at which the
signal or the reference is positive. Both measures are dimensionless
fractions of the analytic peak.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from isoimpact_results import moving_average, window_width  # noqa: E402

# The program's default Output/Filter window [s].
DEFAULT_WINDOW_S = 0.01


def time_step(time):
    """The uniform sampling step of a record; refuses a non-uniform one (the
    moving average counts samples, the RMS weighs them equally)."""
    steps = np.diff(np.asarray(time, dtype=float))
    dt = float(np.median(steps))
    if dt <= 0 or np.max(np.abs(steps - dt)) > 1e-6 * dt + 1e-12:
        raise ValueError("the record is not sampled at a uniform time step "
                         "(set Output/History interval = 1)")
    return dt


def contact_interval(signal, reference):
    """Boolean mask from the first to the last sample where the signal or
    the reference is positive (all False if neither ever is)."""
    active = (np.asarray(signal) > 0) | (np.asarray(reference) > 0)
    mask = np.zeros(len(active), dtype=bool)
    where = np.flatnonzero(active)
    if len(where):
        mask[where[0]:where[-1] + 1] = True
    return mask


def rms(values):
    values = np.asarray(values, dtype=float)
    return float(np.sqrt(np.mean(values * values))) if len(values) else float("nan")


def oscillation_measures(time, signal, reference, reference_peak,
                         window_s=DEFAULT_WINDOW_S):
    """Both measures of one signal: a dict with 'total' (against the
    analytic reference) and 'chatter' (against the signal's own moving
    average over window_s), as fractions of reference_peak, and the
    interval and window actually used."""
    signal = np.asarray(signal, dtype=float)
    reference = np.asarray(reference, dtype=float)
    dt = time_step(time)
    width = window_width(window_s, dt)
    smooth = moving_average(signal, width)
    mask = contact_interval(signal, reference)
    t = np.asarray(time, dtype=float)[mask]
    return {
        "total": rms((signal - reference)[mask]) / reference_peak,
        "chatter": rms((signal - smooth)[mask]) / reference_peak,
        # the deviation of the smooth part alone (model error)
        "smooth_vs_analytic": rms((smooth - reference)[mask]) / reference_peak,
        "window_s": (2 * (width // 2) + 1) * dt,
        "interval_s": (float(t[0]), float(t[-1])) if len(t) else (np.nan, np.nan),
    }


def spectrum(time, signal, reference, above_hz=20.0, share_above_hz=100.0):
    """Where the deviation s - r over the contact interval has its power
    (periodogram with a Hann window, mean removed): the frequency [Hz] of
    the largest peak above above_hz, and the share of the power (without
    the zero frequency) above share_above_hz."""
    mask = contact_interval(signal, reference)
    d = (np.asarray(signal, dtype=float) - np.asarray(reference, dtype=float))[mask]
    d = d - d.mean()
    power = np.abs(np.fft.rfft(d * np.hanning(len(d)))) ** 2
    f = np.fft.rfftfreq(len(d), time_step(time))
    above = f > above_hz
    return {"dominant_hz": float(f[above][np.argmax(power[above])]),
            "share_above": float(power[f > share_above_hz].sum() / power[1:].sum())}
