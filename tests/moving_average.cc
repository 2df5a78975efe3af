// The centred moving average of the summary's filtered peaks
// (isoimpact::moving_average), its peak and width helpers and RunSummary on
// small signals whose averages are exact in floating point: every value is
// asserted to the bit (tolerance 0).
#include <isoimpact/scene/run_summary.h>

#include <string>
#include <vector>

#include "tests.h"

using namespace isoimpact;

namespace
{
  void
  check_signal(const std::string         &what,
               const std::vector<double> &values,
               const std::vector<double> &expected)
  {
    if (!isoimpact_tests::check_true(what + ": " +
                                       std::to_string(expected.size()) +
                                       " samples",
                                     values.size() == expected.size()))
      return;
    for (unsigned int i = 0; i < values.size(); ++i)
      isoimpact_tests::check_close(what + " [" + std::to_string(i) + "]",
                                   values[i],
                                   expected[i],
                                   0.);
  }
} // namespace

int
main()
{
  const std::vector<double> ramp = {0., 1., 2., 3., 4., 5., 6.};

  // A constant stays constant, also where the window is cut.
  check_signal("constant, width 4",
               moving_average(std::vector<double>(7, 2.5), 4),
               std::vector<double>(7, 2.5));

  // A ramp is reproduced inside; at the ends the mean is over the samples
  // present: (0 + 1) / 2 and (5 + 6) / 2.
  check_signal("ramp, width 3",
               moving_average(ramp, 3),
               {0.5, 1., 2., 3., 4., 5., 5.5});
  // Half-width 2: (0 + 1 + 2) / 3, (0 + 1 + 2 + 3) / 4, ...
  check_signal("ramp, width 5",
               moving_average(ramp, 5),
               {1., 1.5, 2., 3., 4., 4.5, 5.});
  // An even width spans one sample more: width 4 is width 5.
  check_signal("ramp, width 4",
               moving_average(ramp, 4),
               moving_average(ramp, 5));
  check_signal("ramp, width 1 (no filter)", moving_average(ramp, 1), ramp);
  check_signal("ramp, width 0 (no filter)", moving_average(ramp, 0), ramp);
  // A window longer than the signal averages all of it everywhere.
  check_signal("window longer than the signal",
               moving_average({1., 2., 3.}, 10),
               {2., 2., 2.});
  check_signal("empty signal", moving_average({}, 3), {});

  // A spike of 6 is spread over 3 samples in the middle, and at the end over
  // the 3, 4 and 5 samples of the cut windows.
  const std::vector<double> spike     = {0., 0., 0., 6., 0., 0., 0.};
  const std::vector<double> end_spike = {0., 0., 0., 0., 0., 0., 6.};
  check_signal("spike, width 3",
               moving_average(spike, 3),
               {0., 0., 2., 2., 2., 0., 0.});
  check_signal("spike at the end, width 5",
               moving_average(end_spike, 5),
               {0., 0., 0., 0., 6. / 5., 1.5, 2.});

  // The peak: its first occurrence; 0 at index 0 if nothing is positive.
  const auto raw_peak      = positive_peak(spike);
  const auto filtered_peak = positive_peak(moving_average(spike, 3));
  CHECK_CLOSE(raw_peak.first, 6., 0.);
  CHECK_TRUE(raw_peak.second == 3);
  CHECK_CLOSE(filtered_peak.first, 2., 0.);
  CHECK_TRUE(filtered_peak.second == 2);
  const auto no_peak = positive_peak({-1., -2., 0.});
  CHECK_CLOSE_ABS(no_peak.first, 0., 0.);
  CHECK_TRUE(no_peak.second == 0);

  // Window widths in samples: round(window / step), at least 1.
  CHECK_TRUE(moving_average_width(0.01, 5e-4) == 20);
  CHECK_TRUE(moving_average_width(1e-4, 5e-4) == 1);
  CHECK_TRUE(moving_average_width(7.5e-4, 5e-4) == 2);

  // RunSummary on five steps of 0.25 s, filter window 0.75 s (3 steps):
  // force 0, 3, 9, 0, 0 and pressure 0, 6, 0, 0, 0; contact from the
  // second to the fourth step; energies 4, 5, 4.5 at the first three steps.
  RunSummary                summary(0.25, 0.75);
  const std::vector<double> forces    = {0., 3., 9., 0., 0.};
  const std::vector<double> pressures = {0., 6., 0., 0., 0.};
  const std::vector<double> energies  = {4., 5., 4.5};
  for (unsigned int i = 0; i < forces.size(); ++i)
    {
      StepRecord step;
      step.time          = 0.25 * i;
      step.contact_force = forces[i];
      step.max_pressure  = pressures[i];
      step.in_contact    = (i >= 1 && i <= 3);
      if (i < energies.size())
        step.total_energy = energies[i];
      summary.add_step(step);
    }
  CHECK_CLOSE(summary.peak_force(), 9., 0.);
  CHECK_CLOSE(summary.time_of_peak_force(), 0.5, 0.);
  CHECK_CLOSE(summary.peak_pressure(), 6., 0.);
  CHECK_CLOSE(summary.contact_duration(), 0.5, 0.);
  CHECK_CLOSE(summary.filter_window(), 0.75, 0.);
  // Filtered force: 1.5, 4, 4, 3, 0 (the first maximum at step 1).
  CHECK_CLOSE(summary.filtered_peak_force().first, 4., 0.);
  CHECK_TRUE(summary.filtered_peak_force().second == 1);
  CHECK_CLOSE(summary.time_of_filtered_peak_force(), 0.25, 0.);
  // Filtered pressure: 3, 2, 2, 0, 0.
  CHECK_CLOSE(summary.filtered_peak_pressure(), 3., 0.);
  CHECK_CLOSE(summary.current_force(), 0., 0.);
  // Errors |5 - 4| / 4 and |4.5 - 4| / 4: the largest, and the last one
  // given (step 2).
  CHECK_CLOSE(summary.max_energy_error(), 0.25, 0.);
  CHECK_CLOSE(summary.current_energy_error(), 0.125, 0.);

  return isoimpact_tests::report();
}
