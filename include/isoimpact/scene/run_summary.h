// Layer 6: the figures of one run that a user compares between runs (peaks,
// filtered peaks, contact duration, energy error), collected step by step,
// and summary.json.
#ifndef isoimpact_run_summary_h
#define isoimpact_run_summary_h

#include <isoimpact/scene/parameters.h>
#include <isoimpact/scene/scene.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  /**
   * The centred moving average of a signal sampled at a uniform step:
   * sample i of the result is the mean of the samples j with
   * |j - i| <= width / 2 (integer division), so the window spans
   * 2 (width / 2) + 1 samples. At the ends of the signal the window is cut
   * and the mean is taken over the samples present. The sums run in
   * increasing j, so the result is reproducible to the bit.
   */
  std::vector<double>
  moving_average(const std::vector<double> &signal, const unsigned int width);

  /**
   * The width in samples of the moving average over a physical window:
   * max(1, round(window / time_step)).
   */
  unsigned int
  moving_average_width(const double window, const double time_step);

  /**
   * The largest positive value of a signal and the index of its first
   * occurrence; (0, 0) if no value is positive.
   */
  std::pair<double, unsigned int>
  positive_peak(const std::vector<double> &signal);

  /**
   * What one step contributes to the summary. The total energy is given
   * only at the steps at which the energy balance is computed.
   */
  struct StepRecord
  {
    double                time          = 0.;
    double                contact_force = 0.; // N/m
    double                max_pressure  = 0.; // Pa
    bool                  in_contact    = false;
    double                penetration   = 0.; // m, deepest
    std::optional<double> total_energy;       // J/m
  };

  /**
   * The running statistics of a run: raw and filtered peaks of the contact
   * force and of the maximal contact pressure, first and last step in
   * contact, and the energy error relative to the first energy given.
   *
   * Penalty contact in explicit dynamics chatters: the raw force and, more
   * so, the pointwise maximal pressure carry oscillations at the period of a
   * few steps. As crash codes do with their contact force output, the
   * summary also gives peaks of the signals filtered with moving_average()
   * over a fixed physical window.
   */
  /**
   * How a run went: its time step against the stable step of the scene, its
   * cost, and whether it completed or was stopped by the stability monitor
   * (status "unstable", with the monitor's reason).
   */
  struct RunFacts
  {
    double         time_step = 0.; // s
    StableTimeStep stable;
    unsigned int   n_steps   = 0;
    double         wall_time = 0.; // s, time loop and output
    // Wall times (s) of the set-up (scene, matrices, time step), the time
    // loop (the initial acceleration and the steps), the output (files,
    // history, energies) and the whole run.
    double setup_wall_time     = 0.;
    double time_loop_wall_time = 0.;
    double output_wall_time    = 0.;
    double total_wall_time     = 0.;
    // The initial acceleration (t = 0, before the first step), part of the
    // time loop's wall time: once per run, not per step.
    double      initial_acceleration_wall_time = 0.;
    std::string status                         = "completed";
    std::string stop_reason;
    // Contact/Mass redistribution: the work of the quasi-static boundary.
    std::optional<BoundarySolveWork> boundary_solve;
    unsigned int                     n_massless_unknowns = 0;
    // Several MPI ranks: whether they met at every step
    // (CentralDifference::ranks_meet_at_every_step()).
    bool ranks_meet_at_every_step = true;
    // ... and each rank's time (s) in waits for the others' messages
    // (UnknownExchange::seconds_waiting(); empty on one process).
    std::vector<double> seconds_waiting_per_rank;
    // Each rank's (one process: its) wall time (s) in the bodies' passes,
    // part of that rank's time loop (CentralDifference::time_in_passes()).
    std::vector<double> seconds_in_passes_per_rank;
  };

  class RunSummary
  {
  public:
    RunSummary(const double time_step, const double filter_window);

    void
    add_step(const StepRecord &record);

    double
    peak_force() const;
    double
    time_of_peak_force() const;
    double
    peak_pressure() const;
    // Last minus first time in contact; 0 without contact. While the
    // contact lasts at the last step (contact_ended() false), the time in
    // contact so far: a lower bound.
    double
    contact_duration() const;
    // Whether the last step recorded is out of contact (true without
    // contact).
    bool
    contact_ended() const;
    double
    current_force() const;
    double
    current_energy_error() const;
    double
    max_energy_error() const;
    // The window of the filter actually used, a whole number of steps.
    double
    filter_window() const;
    std::pair<double, unsigned int>
    filtered_peak_force() const;
    double
    time_of_filtered_peak_force() const;
    double
    filtered_peak_pressure() const;
    // Deepest contact penetration of the run, m.
    double
    max_penetration() const;

    /**
     * Writes summary.json for a run of the scene with the parameters:
     * the set-up, the cost, these statistics, the final displacement of
     * each body's first node and, if the scene has an analytic reference,
     * its figures and the relative errors. The file is written to a
     * temporary name and renamed, so a run that fails leaves no summary.
     */
    void
    write_json(const std::string &path,
               const Parameters  &parameters,
               const std::string &parameter_file,
               const Scene       &scene,
               const RunFacts    &facts) const;

    /**
     * Writes the measured load balancing's passes (several ranks; see
     * UnknownExchange::pass_time_history()) to `path` as CSV, one line per
     * observed pass: who is balanced (a body, or the bodies whole on
     * ranks), the pass's number, each rank's pass time [s] and owned rows.
     * Nothing (and no file) without such passes; by rename like the summary.
     */
    static void
    write_pass_times(const std::string &path, const Scene &scene);

    /**
     * Writes `step_ends` (the end of steps 0, 1, ... on the monotonic clock
     * std::chrono::steady_clock, s; step 0's is the time loop's start, after
     * the initial acceleration and its record) and `passes_until` (the time
     * in the bodies' passes up to each, s) to `path` as CSV: step, time
     * [s], clock [s], the step's time in the passes [s]. By rename.
     */
    static void
    write_step_times(const std::string         &path,
                     const std::vector<double> &step_ends,
                     const std::vector<double> &passes_until,
                     double                     time_step);

  private:
    double              time_step;
    unsigned int        filter_width;
    std::vector<double> times, forces, pressures;
    double              first_contact        = -1.;
    double              last_contact         = -1.;
    bool                in_contact_at_last   = false;
    double              initial_energy       = 0.;
    bool                has_initial_energy   = false;
    double              last_energy_error    = 0.;
    double              largest_energy_error = 0.;
    double              deepest_penetration  = 0.;
  };
} // namespace isoimpact

#endif
