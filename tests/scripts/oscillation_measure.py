"""The oscillation measures of scripts/oscillation.py (doc/oscillation.md) on
synthetic signals with known answers, sampled as the benchmark's history
(dt = 5e-4 s, 0 to 0.9 s):

- a smooth contact pulse (half sine, peak 471.47 N/m, duration 0.749 s, zero
  outside, kinks at both ends as the Hertz force): total deviation against
  itself exactly 0, chatter below 0.2 % of the peak (moving-average bias at
  the kinks and the curvature);
- the pulse plus A sin(2 pi f t) during contact, A = 5 % of the peak: total
  deviation A/sqrt(2) within 1 %; chatter A/sqrt(2) times |1 - H(f)| within
  1 %, H the transfer function of the 21-sample centred moving average
  (H = 0 when the window holds a whole number of periods);
- the spectrum of the deviation peaks at f (within the resolution 1/T) with
  over 99 % of its power above 100 Hz;
- a slow oscillation (5.3 Hz, the scale of the elastic waves, 4 periods in
  the contact) is not chatter: below 5 % of A/sqrt(2) and below the
  smooth-pulse bound, and RMS(moving average - reference) = A/sqrt(2)."""
import math
import os
import sys

import numpy as np

from testing import check_close, check_true, report

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "..", "scripts"))
import isoimpact_results  # noqa: E402
import oscillation  # noqa: E402

dt, peak, duration = 5e-4, 471.47, 0.749
time = np.arange(0, 0.9 + dt / 2, dt)
contact = time <= duration
pulse = np.where(contact, peak * np.sin(math.pi * np.minimum(time, duration) / duration), 0.0)
width = isoimpact_results.window_width(0.01, dt)
samples = 2 * (width // 2) + 1
check_true(f"10 ms at dt = 5e-4 s is a {samples}-sample window", samples == 21)

# The moving average is the program's: truncated at the record's ends.
ma = isoimpact_results.moving_average(np.arange(5.0), 3)
check_true(f"moving average of 0..4 over 3 samples: {ma}",
           np.allclose(ma, [0.5, 1, 2, 3, 3.5]))

smooth = oscillation.oscillation_measures(time, pulse, pulse, peak, 0.01)
check_close("smooth pulse: total deviation", smooth["total"], 0.0, 1e-15, relative=False)
check_close("smooth pulse: chatter (fraction of the peak)", smooth["chatter"], 0.0, 2e-3,
            relative=False)
check_close("contact interval ends at the pulse's last positive sample [s]",
            smooth["interval_s"][1], duration - dt / 2, dt)

amplitude = 0.05 * peak
expected_rms = amplitude / math.sqrt(2) / peak


def transfer(f):
    """Centred moving average of `samples` samples at frequency f."""
    x = math.pi * f * dt
    return math.sin(samples * x) / (samples * math.sin(x))


for f in (4 / (samples * dt), 1 / (6 * dt), 1 / (8 * dt)):  # 381, 333, 250 Hz
    noisy = pulse + np.where(contact, amplitude * np.sin(2 * math.pi * f * time), 0.0)
    m = oscillation.oscillation_measures(time, noisy, pulse, peak, 0.01)
    check_close(f"{f:.0f} Hz: total deviation = A/sqrt(2)", m["total"], expected_rms, 0.01)
    check_close(f"{f:.0f} Hz: chatter = |1 - H| A/sqrt(2), H = {transfer(f):.4f}",
                m["chatter"], abs(1 - transfer(f)) * expected_rms, 0.01)
    spectrum = oscillation.spectrum(time, noisy, pulse)
    check_close(f"{f:.0f} Hz: dominant frequency of the deviation [Hz]",
                spectrum["dominant_hz"], f, 1 / duration, relative=False)
    check_true(f"{f:.0f} Hz: power share above 100 Hz {spectrum['share_above']:.4f} > 0.99",
               spectrum["share_above"] > 0.99)

# 4 periods in the contact duration (5.3 Hz): zero at both ends, no jump.
slow = pulse + np.where(contact, amplitude * np.sin(2 * math.pi * 4 / duration * time), 0.0)
m = oscillation.oscillation_measures(time, slow, pulse, peak, 0.01)
check_close("5.3 Hz: total deviation = A/sqrt(2)", m["total"], expected_rms, 0.01)
check_close("5.3 Hz: in the smooth part, RMS(MA - analytic) = A/sqrt(2)",
            m["smooth_vs_analytic"], expected_rms, 0.01)
check_true(f"5.3 Hz: chatter {m['chatter']:.2e} below the smooth-pulse bound 2e-3 "
           f"and 5 % of A/sqrt(2) = {expected_rms:.2e}",
           m["chatter"] < min(2e-3, 0.05 * expected_rms))

# A record with a gap in time is refused.
try:
    oscillation.oscillation_measures(np.array([0, 1, 3.0]), np.zeros(3), np.zeros(3), 1.0)
    check_true("non-uniform record refused", False)
except ValueError:
    check_true("non-uniform record refused", True)
report()
