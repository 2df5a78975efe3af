// Layer 6: the run summary and the moving-average filter.
#include <isoimpact/scene/output.h>
#include <isoimpact/scene/run_summary.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

using namespace dealii;

namespace isoimpact
{
  std::vector<double>
  moving_average(const std::vector<double> &signal, const unsigned int width)
  {
    const int           half = width / 2, n = signal.size();
    std::vector<double> average(n);
    for (int i = 0; i < n; ++i)
      {
        double sum   = 0.;
        int    count = 0;
        for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half); ++j)
          sum += signal[j], ++count;
        average[i] = sum / count;
      }
    return average;
  }



  unsigned int
  moving_average_width(const double window, const double time_step)
  {
    return std::max(1u,
                    static_cast<unsigned int>(std::round(window / time_step)));
  }



  std::pair<double, unsigned int>
  positive_peak(const std::vector<double> &signal)
  {
    std::pair<double, unsigned int> peak{0., 0};
    for (unsigned int i = 0; i < signal.size(); ++i)
      if (signal[i] > peak.first)
        peak = {signal[i], i};
    return peak;
  }



  RunSummary::RunSummary(const double time_step, const double filter_window)
    : time_step(time_step)
    , filter_width(moving_average_width(filter_window, time_step))
  {}



  void
  RunSummary::add_step(const StepRecord &record)
  {
    times.push_back(record.time);
    forces.push_back(record.contact_force);
    pressures.push_back(record.max_pressure);
    deepest_penetration = std::max(deepest_penetration, record.penetration);
    in_contact_at_last  = record.in_contact;
    if (record.in_contact)
      {
        if (first_contact < 0.)
          first_contact = record.time;
        last_contact = record.time;
      }
    if (record.total_energy)
      {
        if (!has_initial_energy)
          initial_energy = *record.total_energy, has_initial_energy = true;
        last_energy_error =
          std::abs(*record.total_energy - initial_energy) / initial_energy;
        largest_energy_error =
          std::max(largest_energy_error, last_energy_error);
      }
  }



  double
  RunSummary::max_penetration() const
  {
    return deepest_penetration;
  }



  double
  RunSummary::peak_force() const
  {
    return positive_peak(forces).first;
  }



  double
  RunSummary::time_of_peak_force() const
  {
    const auto peak = positive_peak(forces);
    return peak.first > 0. ? times[peak.second] : 0.;
  }



  double
  RunSummary::peak_pressure() const
  {
    return positive_peak(pressures).first;
  }



  double
  RunSummary::contact_duration() const
  {
    return (first_contact >= 0.) ? last_contact - first_contact : 0.;
  }



  bool
  RunSummary::contact_ended() const
  {
    return !in_contact_at_last;
  }



  double
  RunSummary::current_force() const
  {
    return forces.empty() ? 0. : forces.back();
  }



  double
  RunSummary::current_energy_error() const
  {
    return last_energy_error;
  }



  double
  RunSummary::max_energy_error() const
  {
    return largest_energy_error;
  }



  double
  RunSummary::filter_window() const
  {
    return filter_width * time_step;
  }



  std::pair<double, unsigned int>
  RunSummary::filtered_peak_force() const
  {
    return positive_peak(moving_average(forces, filter_width));
  }



  double
  RunSummary::time_of_filtered_peak_force() const
  {
    return filtered_peak_force().second * time_step;
  }



  double
  RunSummary::filtered_peak_pressure() const
  {
    return positive_peak(moving_average(pressures, filter_width)).first;
  }



  namespace
  {
    // The position and displacement of a body's first node (the first
    // unknown of component 1 and the unknown of component 0 at the same
    // place): a probe that the output tests compare with the ParaView files.
    nlohmann::ordered_json
    displacement_probe(const ElasticBody<2> &body)
    {
      const auto             &disc = body.discretization();
      types::global_dof_index ix = 0, iy = 0;
      for (types::global_dof_index i = 0; i < body.n_dofs(); ++i)
        if (disc.dof_component(i) == 1)
          {
            iy = i;
            break;
          }
      for (types::global_dof_index i = 0; i < body.n_dofs(); ++i)
        if (disc.dof_component(i) == 0 &&
            disc.dof_position(i).distance(disc.dof_position(iy)) < 1e-12)
          {
            ix = i;
            break;
          }
      const Point<2> p = disc.dof_position(iy);
      return {{"body", body.name()},
              {"x_m", p[0]},
              {"y_m", p[1]},
              {"ux_m", body.displacement(ix)},
              {"uy_m", body.displacement(iy)}};
    }
  } // namespace



  void
  RunSummary::write_json(const std::string &path,
                         const Parameters  &parameters,
                         const std::string &parameter_file,
                         const Scene       &scene,
                         const RunFacts    &facts) const
  {
    nlohmann::ordered_json summary;
    summary["parameter_file"] = parameter_file;
    summary["discretization"] = scene.bodies[0]->discretization().name();
    summary["mass_matrix"]    = to_string(parameters.mass_scheme);
    summary["unknowns"]       = scene.n_dofs();
    summary["cells"]          = nlohmann::ordered_json::array();
    for (const auto &body : scene.bodies)
      summary["cells"].push_back(
        body->discretization().triangulation().n_active_cells());
    summary["vtu_subdivisions"] = parameters.vtu_subdivisions;
    summary["vtu_cells"] =
      parameters.vtu_higher_order ? "higher order" : "subdivided";
    summary["status"] = facts.status;
    if (!facts.stop_reason.empty())
      summary["stop_reason"] = facts.stop_reason;
    summary["time_step_s"]              = facts.time_step;
    summary["time_step_automatic"]      = parameters.automatic_time_step;
    summary["stable_time_step_bound_s"] = facts.stable.bound();
    summary["stable_time_step_element_bound_s"] = facts.stable.element_bound;
    summary["stable_time_step_gershgorin_bound_s"] =
      facts.stable.gershgorin_bound;
    summary["stable_time_step_estimate_s"] = facts.stable.power_estimate;
    summary["steps"]                       = facts.n_steps;
    summary["wall_time_s"]                 = facts.wall_time;
    summary["wall_time_parts_s"]           = {{"setup", facts.setup_wall_time},
                                              {"time_loop", facts.time_loop_wall_time},
                                              {"output", facts.output_wall_time},
                                              {"total", facts.total_wall_time}};
    // Part of the time loop, once per run (its time per step is the loop's
    // less this, over the steps).
    summary["initial_acceleration_s"] = facts.initial_acceleration_wall_time;
    summary["mass_redistribution"]    = parameters.mass_redistribution;
    if (facts.boundary_solve)
      {
        const BoundarySolveWork &w     = *facts.boundary_solve;
        const double             steps = std::max<double>(1., double(w.solves));
        summary["boundary_solve"]      = {
               {"massless_unknowns", facts.n_massless_unknowns},
               {"solves", w.solves},
               {"contact_evaluations", w.evaluations},
               {"back_substitutions", w.substitutions},
               {"factorizations", w.factorizations},
               {"step_cuts", w.step_cuts},
               {"loose_solves", w.loose_solves},
               {"stalled_solves", w.stalled_solves},
               {"contact_evaluations_per_step", w.evaluations / steps},
               {"factorizations_per_step", w.factorizations / steps},
               {"max_contact_evaluations_per_step", w.max_evaluations},
               {"max_relative_residual", w.max_residual_ratio}};
      }
    // Several MPI ranks: each body's split at the end (load balancing).
    summary["mpi_ranks"] = n_world_ranks();
    summary["thread_partition"] =
      parameters.pass_of_body_on_one_thread ? "by body" : "dynamic";
    summary["bodies_whole_on_ranks"]    = scene.bodies_on_ranks;
    summary["ranks_meet_at_every_step"] = facts.ranks_meet_at_every_step;
    summary["mpi_wait_s_per_rank"]      = facts.seconds_waiting_per_rank;
    // Part of each rank's time loop: the rest is the contacts, the waits
    // and the step's end (and the initial acceleration).
    summary["passes_s_per_rank"] = facts.seconds_in_passes_per_rank;
    // Per contact: "none" (each process computes all of it), "shared
    // memory" or "messages" (the ranks share its Gauss points).
    summary["contact_point_exchange"] = nlohmann::ordered_json::array();
    for (const auto &contact : scene.contacts)
      summary["contact_point_exchange"].push_back(contact->point_exchange());
    summary["rank_splits"] = nlohmann::ordered_json::array();
    for (const auto &body : scene.bodies)
      {
        const UnknownExchange &exchange = body->exchange();
        if (!exchange.is_distributed())
          continue;
        summary["rank_splits"].push_back(
          {{"body", body->name()},
           {"unknowns", body->n_dofs()},
           {"load_balancing", exchange.balances_load()},
           {"claims_band", exchange.claims_band()},
           {"shares_state", exchange.shares_state()},
           {"split_layers", exchange.split()},
           {"band_chunks", exchange.n_band_chunks()},
           {"band_chunks_of_rank_0", exchange.n_chunks_of_rank_0()},
           {"split_bounds_layers",
            {exchange.split_bounds().first, exchange.split_bounds().second}},
           {"moves", exchange.n_moves()},
           {"moves_without_meeting", exchange.n_moves_without_meeting()},
           {"owned_unknowns_per_rank", exchange.owned_counts()},
           {"pass_time_per_row_s", exchange.pass_time_per_row()}});
      }
    summary["symmetry_factor"] = scene.symmetry_factor;
    summary["obstacle"]        = parameters.obstacle.type;

    const auto filtered_force             = filtered_peak_force().first;
    summary["peak_contact_force_N_per_m"] = peak_force();
    summary["time_of_peak_force_s"]       = time_of_peak_force();
    summary["contact_duration_s"]         = contact_duration();
    summary["contact_ended"]              = contact_ended();
    summary["peak_contact_pressure_Pa"]   = peak_pressure();
    summary["filter_window_s"]            = filter_window();
    summary["filtered_peak_contact_force_N_per_m"] = filtered_force;
    summary["time_of_filtered_peak_force_s"] = time_of_filtered_peak_force();
    summary["filtered_peak_contact_pressure_Pa"] = filtered_peak_pressure();
    summary["max_energy_error"]                  = max_energy_error();
    summary["max_penetration_m"]                 = max_penetration();
    summary["final_displacement_probe"] = nlohmann::ordered_json::array();
    for (const auto &body : scene.bodies)
      summary["final_displacement_probe"].push_back(displacement_probe(*body));

    if (scene.reference)
      {
        const auto &ref = *scene.reference;
        const auto  rel = [](const double value, const double reference) {
          return (value - reference) / reference;
        };
        summary["analytic"]       = {{"approach_law", parameters.approach_law},
                                     {"peak_contact_force_N_per_m", ref.peak_force()},
                                     {"time_of_peak_force_s", ref.time_of_peak()},
                                     {"contact_duration_s", ref.contact_duration()},
                                     {"peak_contact_pressure_Pa",
                                      ref.peak_pressure()}};
        summary["relative_error"] = {
          {"peak_contact_force", rel(peak_force(), ref.peak_force())},
          {"time_of_peak_force", rel(time_of_peak_force(), ref.time_of_peak())},
          // Still in contact at the end: no duration to compare.
          {"contact_duration",
           contact_ended() ?
             nlohmann::ordered_json(
               rel(contact_duration(), ref.contact_duration())) :
             nlohmann::ordered_json()},
          {"peak_contact_pressure", rel(peak_pressure(), ref.peak_pressure())},
          {"filtered_peak_contact_force",
           rel(filtered_force, ref.peak_force())},
          {"time_of_filtered_peak_force",
           rel(time_of_filtered_peak_force(), ref.time_of_peak())},
          {"filtered_peak_contact_pressure",
           rel(filtered_peak_pressure(), ref.peak_pressure())}};
      }

    write_by_rename(path, [&](std::ostream &out) {
      out << summary.dump(2) << '\n';
    });
  }

  void
  RunSummary::write_pass_times(const std::string &path, const Scene &scene)
  {
    std::vector<std::pair<std::string, const UnknownExchange *>> balanced;
    for (const auto &body : scene.bodies)
      if (!body->exchange().pass_time_history().empty())
        balanced.emplace_back(body->exchange().balances_whole_body() ?
                                "bodies whole on ranks" :
                                body->name(),
                              &body->exchange());
    if (balanced.empty())
      return;
    write_by_rename(path, [&](std::ostream &out) {
      out << "balanced,pass,rank_0_pass_s,rank_1_pass_s,rank_0_rows,"
             "rank_1_rows,rank_0_pass_end_s,rank_1_pass_end_s\n"
          << std::setprecision(17);
      for (const auto &[name, exchange] : balanced)
        {
          unsigned int pass = 0;
          for (const auto &record : exchange->pass_time_history())
            out << name << ',' << ++pass << ',' << record.seconds[0] << ','
                << record.seconds[1] << ',' << record.rows[0] << ','
                << record.rows[1] << ',' << record.ends[0] << ','
                << record.ends[1] << '\n';
        }
    });
  }

  void
  RunSummary::write_step_times(const std::string         &path,
                               const std::vector<double> &step_ends,
                               const std::vector<double> &passes_until,
                               const double               time_step)
  {
    write_by_rename(path, [&](std::ostream &out) {
      out << "step,time_s,monotonic_clock_s,passes_s\n"
          << std::setprecision(17);
      for (std::size_t step = 0; step < step_ends.size(); ++step)
        out << step << ',' << step * time_step << ',' << step_ends[step] << ','
            << (step == 0 ? 0. : passes_until[step] - passes_until[step - 1])
            << '\n';
    });
  }
} // namespace isoimpact
