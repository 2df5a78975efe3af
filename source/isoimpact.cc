/* ---------------------------------------------------------------------------
 * isoimpact: explicit contact-impact dynamics with classical and
 * isogeometric finite elements, on top of deal.II.
 *
 * This is the main program. It reads like a deal.II tutorial program: the
 * library (include/isoimpact) provides the pieces, layer by layer, and this
 * file puts them together for one run described by a parameter file.
 * ---------------------------------------------------------------------------
 *
 * @sect3{Introduction}
 *
 * Two elastic bodies fly towards each other and touch at t = 0. We solve the
 * equations of linear elastodynamics (small strains, plane strain)
 *   M a + K u = f_c(u)
 * in which f_c are the forces of a frictionless penalty contact. Its
 * virtual work is integrated over both contact boundaries (a symmetric
 * "two-pass" formulation, so neither body is master):
 *   delta Pi_c = eps * int_{Gamma_1} g delta g + eps * int_{Gamma_2} g delta g
 * with the normal gap g of a point of one surface to the closest point of
 * the other, active where g < 0. See doc/formulation.md.
 *
 * Time is integrated with central differences, an explicit scheme: every
 * step needs only a product with the stiffness matrix and a solve with the
 * mass matrix, which is a division when the mass is lumped (row-sum or HRZ)
 * and a back-substitution with a factorisation computed once when it is
 * consistent. The scheme is stable for time steps below 2/omega_max, and
 * the contact penalty raises omega_max. The program bounds that limit from
 * below with the contact springs included (doc/stability.md), takes a safe
 * fraction of it with Time step = auto, refuses a given step above it, and
 * watches every step so that a run that blows up stops with a message
 * instead of writing garbage.
 *
 * The reference problem is the dynamic Hertz impact of two cylinders
 * (doc/hertz-reference.md): the program writes the analytic contact force
 * and pressure next to the computed ones.
 *
 * A scene may also be reduced to what it requires: one body against a
 * rigid, fixed, frictionless obstacle (a plane or a cylinder, subsection
 * Obstacle). The symmetric impact of two equal cylinders is then modelled as
 * one cylinder against its symmetry plane. The time integrator sees the
 * obstacle through the same ContactModel interface as the two-body contact,
 * so the loop below, the energy balance and the output do not change.
 *
 * The same program runs on several MPI ranks (mpirun -np N): every rank
 * builds the whole scene, and each step computes on each rank the rows of
 * the unknowns that rank owns; the bodies exchange the displacements at the
 * ranks' interfaces and the contact surfaces' after each step
 * (doc/parallel.md). Rank 0 writes the files and the progress.
 */

// @sect3{Include files}
//
// deal.II's utilities for timing and parallel-ready output streams, and the
// library's layers: the scene (layer 6) pulls in the time integrator (5),
// the mechanics (4) and the discretisations (3); the output files and the
// run summary are in layer 6 too.
#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <isoimpact/scene/output.h>
#include <isoimpact/scene/parameters.h>
#include <isoimpact/scene/run_summary.h>
#include <isoimpact/scene/scene.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // Several MPI ranks: returns once every rank has called it.
    void
    wait_for_all_ranks()
    {
      if (n_world_ranks() > 1)
        {
          const int ierr = MPI_Barrier(MPI_COMM_WORLD);
          AssertThrowMPI(ierr);
        }
    }
  } // namespace

  // @sect3{The <code>ImpactProgram</code> class}
  //
  // As in step-48, the class holds the pieces of one explicit dynamics run:
  // the scene (bodies, contact, reference), the time integrator, and the
  // output. The figures for the summary are collected along the way by a
  // RunSummary.
  class ImpactProgram
  {
  public:
    ImpactProgram(const Parameters  &parameters,
                  const std::string &parameter_file);
    // Returns the exit code: 0 if the run completed, 1 if the stability
    // monitor stopped it.
    int
    run();

  private:
    void
    print_setup();
    void
    open_output();
    ContactResult<2>
    contact_on_first_body() const;
    std::string
    record(const bool write_solution, const bool write_profile);
    std::string
    unstable_message(const std::string &reason) const;
    void
    print_progress();

    const Parameters  parameters;
    const std::string parameter_file;

    // Rank 0 writes the files and prints; on one process it is the only one.
    const unsigned int n_ranks;
    const bool         is_root;
    ConditionalOStream pcout;

    Scene                                 scene;
    std::unique_ptr<CentralDifference<2>> integrator;
    std::unique_ptr<SolutionWriter>       solution_writer;
    std::unique_ptr<HistoryWriter>        history;
    std::unique_ptr<StabilityMonitor<2>>  monitor;
    std::unique_ptr<RunSummary>           summary;
    StableTimeStep                        stable;
    double                                time_step          = 0.;
    double                                selected_time_step = 0.;
    std::uint64_t                         n_steps            = 0;
    unsigned int                          next_profile       = 0;
    Timer                                 wall_clock;
    // For summary.json: the parts of the run's wall time (s), accumulated
    // by Laps, and the start of the run (the constructor).
    double setup_time = 0., loop_time = 0., output_time = 0.,
           paraview_time = 0.;
    const std::chrono::steady_clock::time_point start_of_run =
      std::chrono::steady_clock::now();
  };

  // Adds the wall time of its scope to `seconds`. std::chrono: deal.II's
  // Timer and TimerOutput reduce over MPI at every stop, which cost more
  // than a time step on a loaded machine.
  class Lap
  {
  public:
    explicit Lap(double &seconds)
      : seconds(seconds)
      , start(std::chrono::steady_clock::now())
    {}
    ~Lap()
    {
      seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
    }

  private:
    double                                     &seconds;
    const std::chrono::steady_clock::time_point start;
  };



  // @sect3{Set-up}
  //
  // Building the scene does all the work that is done once: meshes (or NURBS
  // patches), unknowns and constraints, stiffness and mass matrices, lumping,
  // the factorisation of a consistent mass, and the contact surfaces. Bad
  // input is detected here, before anything is written to disk.
  ImpactProgram::ImpactProgram(const Parameters  &parameters,
                               const std::string &parameter_file)
    : parameters(parameters)
    , parameter_file(parameter_file)
    , n_ranks(n_world_ranks())
    , is_root(world_rank() == 0)
    , pcout(std::cout, is_root)
  {}



  void
  ImpactProgram::print_setup()
  {
    pcout << "isoimpact: " << parameter_file << '\n';
    for (const auto &body : scene.bodies)
      pcout << "  " << body->name() << ": " << body->discretization().name()
            << ", " << body->discretization().triangulation().n_active_cells()
            << " cells, " << body->n_dofs() << " unknowns, mass "
            << body->total_mass() << " kg/m (" << to_string(body->mass_scheme())
            << ")\n";
    const auto [memory, cells] = estimated_memory_and_cells(parameters);
    pcout << "  estimated memory " << std::setprecision(3) << memory / 1e9
          << " GB for about " << std::llround(cells)
          << " cells (checked against the available memory)\n"
          << std::setprecision(6);
    pcout << "  contact: " << scene.contacts[0]->description() << '\n';
    if (n_ranks > 1 && scene.bodies_on_ranks)
      pcout << "  " << n_ranks << " MPI ranks; each body whole on a rank of "
            << "its own (body b on rank b - 1), the contact surfaces "
            << "exchanged (Parallel/Distribution)\n";
    else if (n_ranks > 1)
      pcout << "  " << n_ranks << " MPI ranks; each computes the rows of its "
            << "own unknowns (body 1: "
            << scene.bodies[0]->exchange().owned_unknowns().size()
            << " on rank 0)\n";
    // The load balancing in force (automatic resolved by UnknownExchange:
    // shared memory for bodies whole on ranks on one node, else measured).
    bool shares_state = false;
    for (const auto &body : scene.bodies)
      if (body->exchange().balances_load())
        {
          shares_state = body->exchange().shares_state();
          pcout << "  load balancing: "
                << load_balancing_names.to_string(
                     body->exchange().load_balancing())
                << (parameters.load_balancing == LoadBalancing::automatic ?
                      " (automatic: shared memory for bodies whole on "
                      "ranks where both ranks are on one node and /dev/shm "
                      "has room for the state, else measured)\n" :
                      "\n");
          break;
        }
    if (n_ranks > 1)
      pcout << "  the ranks "
            << (integrator->ranks_meet_at_every_step() ?
                  "meet at every step (consistent mass, hanging nodes, "
                  "mass redistribution, bipenalty or contact damping)\n" :
                shares_state ?
                  "need not meet at every step: each waits for the "
                  "other's pass only, and the energies are summed one step "
                  "late\n" :
                  "need not meet at every step: each sends the displacement "
                  "the others read from its pass, and the energies are "
                  "summed one step late\n");
    for (const auto &contact : scene.contacts)
      if (contact->point_exchange() != "none")
        pcout << "  the ranks share the contact's Gauss points and exchange "
                 "what the projections found in "
              << (contact->point_exchange() == "messages" ?
                    "messages (MPI_Allgather)" :
                    "shared memory")
              << " (Parallel/Contact point exchange)\n";
    if (parameters.mass_redistribution)
      {
        pcout << "  mass redistribution: massless contact surfaces (";
        for (const auto &body : scene.bodies)
          pcout << body->massless_dofs().size()
                << (&body == &scene.bodies.back() ? "" : ", ");
        pcout << " unknowns), solved quasi-statically; the stable step is "
                 "that of the interior\n";
      }
    if (parameters.obstacle.active())
      pcout << "  scene reduction: Body 1 against a rigid obstacle; Body 2 "
               "is ignored\n";
    if (scene.symmetry_factor != 1.)
      pcout << "  symmetry: half of each body is modelled; contact force "
               "and energies are reported for the full bodies (factor "
            << scene.symmetry_factor << ")\n";
    // Both stable steps include the contact penalty: the guaranteed bound
    // (the larger of the element-by-element and the Gershgorin bound; a
    // bound that does not apply to the scene is 0) and the sharper
    // power-iteration estimate.
    const auto bound_text = [](const double bound) {
      std::ostringstream text;
      if (bound > 0.)
        text << bound << " s";
      else
        text << "not applicable";
      return text.str();
    };
    pcout << "  time step " << time_step << " s"
          << (parameters.automatic_time_step ? " (auto: " : " (")
          << time_step / stable.bound()
          << " of the stable step bound); stable step with contact: bound "
          << stable.bound() << " s (element "
          << bound_text(stable.element_bound) << ", Gershgorin "
          << bound_text(stable.gershgorin_bound) << "), estimate "
          << stable.power_estimate << " s\n";
    if (time_step > stable.bound())
      pcout << "  warning: the time step exceeds the stable step bound "
               "(allowed by 'Allow time step above the stable estimate'); "
               "the stability monitor stops the run if it blows up\n";
    // A contact zone resolved by one or two faces gives peaks several
    // times too high: say so before the run.
    if (const double faces = faces_across_contact_zone(scene, parameters);
        faces > 0.)
      {
        pcout << "  contact zone: the analytic contact width at the peak "
                 "spans "
              << faces << " faces of body 1's surface";
        if (faces < recommended_faces_across_contact_zone)
          pcout << "\n  warning: fewer than "
                << recommended_faces_across_contact_zone
                << " faces across the contact zone: expect peak force and "
                   "pressure errors of several percent or more; refine "
                   "(Discretization/Global or Local refinements)";
        pcout << '\n';
      }
    pcout << "  " << n_steps << " steps to t = " << parameters.end_time << " s";
    if (time_step != selected_time_step)
      pcout << " (the step " << selected_time_step
            << " s shortened so that the last step ends at the end time)";
    pcout << "; output in " << parameters.output_directory << std::endl;
  }



  // @sect3{Output files}
  //
  // The output directory is created only once the scene is built, so that a
  // bad parameter file leaves nothing behind. The files an earlier run wrote
  // there (the names this program writes, nothing else) are removed first,
  // so that none of them is mixed with the new ones. history.csv gets one
  // row per output step; its header says the unit of every column.
  void
  ImpactProgram::open_output()
  {
    const std::string &directory = parameters.output_directory;
    // Several MPI ranks: every rank writes the ParaView pieces of its own
    // cells into the directory rank 0 prepares.
    const auto make_solution_writer = [&]() {
      solution_writer =
        std::make_unique<SolutionWriter>(directory,
                                         parameters.vtu_subdivisions,
                                         parameters.vtu_higher_order,
                                         parameters.vtu_compression);
    };
    if (!is_root)
      {
        wait_for_all_ranks(); // the directory, below
        make_solution_writer();
        return;
      }
    std::filesystem::create_directories(directory);
    const std::regex owned(
      "(parameters\\.prm|history\\.csv|summary\\.json|solution\\.pvd|"
      "solution_[0-9]+\\.pvtu|body[0-9]+_[0-9]+(\\.[0-9]+)?\\.vtu|"
      "contact_pressure_t[0-9.]+\\.csv|pass_times\\.csv|step_times\\.csv)"
      "(\\.tmp)?");
    unsigned int n_removed = 0;
    for (const auto &entry : std::filesystem::directory_iterator(directory))
      if (entry.is_regular_file() &&
          std::regex_match(entry.path().filename().string(), owned))
        n_removed += std::filesystem::remove(entry.path());
    if (n_removed > 0)
      pcout << "  removed " << n_removed << " files of an earlier run from "
            << directory << std::endl;
    std::filesystem::copy_file(
      parameter_file,
      directory + "/parameters.prm",
      std::filesystem::copy_options::overwrite_existing);
    wait_for_all_ranks();
    make_solution_writer();
    history = std::make_unique<HistoryWriter>(directory + "/history.csv",
                                              parameter_file,
                                              parameters,
                                              scene);
  }



  // @sect3{Recording a step}
  //
  // The contact force is the resultant of the contact tractions on body 1,
  // projected on the line of impact; with a half model it is doubled to give
  // the force between the full cylinders, as the analytic reference does.
  // Every step goes into the summary; the energy balance costs two
  // matrix-vector products and is computed only at history steps, where the
  // stability monitor checks the total energy too. The step is recorded only
  // if it is sound; else record() returns what went wrong.
  ContactResult<2>
  ImpactProgram::contact_on_first_body() const
  {
    // Summed over the interactions that act on body 1 (a channel has two).
    ContactResult<2> sum;
    const auto      &results = integrator->contact_results();
    for (unsigned int i = 0; i < results.size(); ++i)
      {
        const auto  &interaction = scene.interactions[i];
        const double sign        = (interaction.first_body == 0)  ? 1. :
                                   (interaction.second_body == 0) ? -1. :
                                                                    0.;
        const auto  &result      = results[i];
        sum.energy += result.energy;
        sum.force_on_body_0 += sign * result.force_on_body_0;
        sum.max_pressure = std::max(sum.max_pressure, result.max_pressure);
        sum.max_gauss_point_pressure =
          std::max(sum.max_gauss_point_pressure,
                   result.max_gauss_point_pressure);
        sum.max_penetration =
          std::max(sum.max_penetration, result.max_penetration);
        sum.n_active_points += result.n_active_points;
        sum.points.insert(sum.points.end(),
                          result.points.begin(),
                          result.points.end());
      }
    return sum;
  }



  std::string
  ImpactProgram::record(const bool write_solution, const bool write_profile)
  {
    const ContactResult<2> result = contact_on_first_body();
    StepRecord             step;
    step.time = integrator->time();
    step.contact_force =
      scene.symmetry_factor * (result.force_on_body_0 * scene.impact_direction);
    step.max_pressure = result.max_pressure;
    step.in_contact   = result.n_active_points > 0;
    step.penetration  = result.max_penetration;

    if (integrator->step_number() % parameters.history_interval == 0)
      {
        const EnergyBalance energy = integrator->energy_balance();
        const std::string failure = monitor->check_total_energy(energy.total());
        if (!failure.empty())
          return failure;
        step.total_energy = scene.symmetry_factor * energy.total();
        if (is_root)
          history->write(
            step.time,
            step.contact_force,
            step.max_pressure,
            result.max_gauss_point_pressure,
            energy,
            integrator->quasi_static_boundary() ?
              integrator->quasi_static_boundary()->work().last_evaluations :
              0);
      }
    summary->add_step(step);

    if (write_solution)
      {
        const Lap lap(paraview_time);
        // Several ranks: each holds its own rows of the state and receives
        // the rest, then writes the pieces of its own cells.
        for (auto *body : scene.body_pointers())
          body->gather_state();
        solution_writer->write(
          scene.body_pointers(),
          step.time,
          contact_pressure_nodal_values(scene, integrator->contact_results()));
      }
    // The pressure along the contact surface at a requested time.
    if (write_profile && is_root)
      write_pressure_profile(parameters.output_directory,
                             step.time,
                             result.points,
                             scene.impact_direction,
                             scene.reference.get());
    return "";
  }



  std::string
  ImpactProgram::unstable_message(const std::string &reason) const
  {
    std::ostringstream message;
    message << "the run became unstable at step " << integrator->step_number()
            << " (t = " << integrator->time() << " s): " << reason
            << ". Time step " << time_step << " s against the stable step "
            << "bound " << stable.bound() << " s (estimate "
            << stable.power_estimate
            << " s), both with the contact penalty; the output holds the "
               "steps before the instability";
    return message.str();
  }



  void
  ImpactProgram::print_progress()
  {
    const double elapsed = wall_clock.wall_time();
    const double done    = double(integrator->step_number()) / n_steps;
    if (is_root)
      history->flush(); // whole rows, so that a stopped run leaves them
    pcout << "  step " << std::setw(6) << integrator->step_number() << "/"
          << n_steps << "  t = " << std::fixed << std::setprecision(4)
          << integrator->time() << " s  contact force = " << std::setw(9)
          << std::setprecision(2) << summary->current_force()
          << " N/m  energy error = " << std::setprecision(3)
          << 100. * summary->current_energy_error() << " %  elapsed "
          << std::setprecision(1) << elapsed << " s, left ~"
          << elapsed * (1. - done) / std::max(done, 1e-12) << " s"
          << std::defaultfloat << std::setprecision(6) << std::endl;
  }



  // @sect3{The time loop}
  //
  // The time step is chosen once the scene is built, because its bound
  // depends on the matrices and the contact surfaces: Time step = auto takes
  // the safety factor times the bound, and a given step above the bound is
  // refused here, before any output. After set-up, the loop is short:
  // advance one step, let the stability monitor check it, and at output
  // steps record the history, the ParaView files and the pressure profiles.
  int
  ImpactProgram::run()
  {
    {
      const Lap lap(setup_time);
      check_scene(parameters, parameter_file, n_ranks);
      scene              = build_scene(parameters);
      stable             = scene_stable_time_step(scene.body_pointers(),
                                      scene.interactions,
                                      parameters.contact_activation_margin);
      selected_time_step = select_time_step(parameters, stable, parameter_file);
      // The last step lands on the end time: the step is shortened to
      // End time / n (at most by a factor (n - 1) / n).
      const TimeSteps steps =
        time_steps_to_end(parameters, selected_time_step, parameter_file);
      n_steps   = steps.n_steps;
      time_step = steps.time_step;
      summary =
        std::make_unique<RunSummary>(time_step, parameters.filter_window);
      integrator = std::make_unique<CentralDifference<2>>(scene.body_pointers(),
                                                          scene.interactions,
                                                          time_step);
      // Several ranks that meet at every step share the contact's
      // projections; ranks that need not meet each project every point
      // rather than wait for the others' (doc/parallel.md, session 34),
      // except where every body's state lies in shared memory: those
      // ranks wait for each other's pass before the contacts anyway, and
      // exchange the projections in that memory too (session 47).
      const auto bodies = scene.body_pointers();
      const bool state_shared =
        std::all_of(bodies.begin(), bodies.end(), [](const auto *body) {
          return body->exchange().shares_state();
        });
      if (n_world_ranks() > 1 &&
          (integrator->ranks_meet_at_every_step() || state_shared))
        for (auto &contact : scene.contacts)
          contact->distribute_points(MPI_COMM_WORLD,
                                     parameters.contact_point_exchange);
      // Rank 0 alone records the history and the summary: the other ranks
      // project the contact pressures only for the output's records.
      if (!is_root)
        for (auto &contact : scene.contacts)
          contact->set_pressures_at_every_step(false);
    }
    print_setup();
    {
      const Lap lap(output_time);
      open_output();
    }

    wall_clock.restart();
    const auto is_vtu_step = [&](const std::uint64_t step) {
      return parameters.vtu_interval > 0 &&
             (step % parameters.vtu_interval == 0 || step == n_steps);
    };
    // A profile is written at the first step at or after each requested time.
    const auto profile_due = [&]() {
      return next_profile < parameters.profile_times.size() &&
             integrator->time() >=
               parameters.profile_times[next_profile] - 1e-12;
    };

    double initial_acceleration_time = 0.;
    {
      const Lap lap(loop_time);
      const Lap initial(initial_acceleration_time);
      integrator->initialize(true);
    }
    std::optional<Lap> first_record(std::in_place, output_time);
    StabilityLimits    limits;
    limits.input_energy            = integrator->energy_balance().total();
    limits.energy_growth_tolerance = parameters.energy_growth_tolerance;
    limits.maximum_penetration =
      parameters.maximum_penetration * parameters.smallest_body_size();
    monitor = std::make_unique<StabilityMonitor<2>>(*integrator, limits);
    std::string failure = record(is_vtu_step(0), false);
    first_record.reset();
    const std::uint64_t progress_every =
      std::max<std::uint64_t>(1, n_steps * parameters.progress_interval / 100.);
    // Output/Step times: the end of each step on the monotonic clock, for
    // benchmarks that hold and resume the run, and the time in the bodies'
    // passes up to it (rank 0's; the ranks move together); "step 0" is the
    // loop's start.
    std::vector<double> step_ends, passes_until;
    const auto          note_step_end = [&]() {
      if (parameters.step_times && is_root)
        {
          step_ends.push_back(
            std::chrono::duration<double>(
              std::chrono::steady_clock::now().time_since_epoch())
              .count());
          passes_until.push_back(integrator->time_in_passes());
        }
    };
    note_step_end();
    for (std::uint64_t step = 1; step <= n_steps && failure.empty(); ++step)
      {
        const double next_time = step * time_step;
        const bool   profile =
          next_profile < parameters.profile_times.size() &&
          next_time >= parameters.profile_times[next_profile] - 1e-12;
        {
          const Lap lap(loop_time);
          // The contact points and nodal pressures for the profile and
          // the ParaView output; the whole-step velocity for the latter
          // only (the other steps do not read it).
          integrator->advance(profile || is_vtu_step(step), is_vtu_step(step));
          failure = monitor->check();
        }
        note_step_end();
        if (!failure.empty())
          break;
        {
          const Lap lap(output_time);
          failure = record(is_vtu_step(step), profile_due());
          while (profile_due())
            ++next_profile;
          if (step % progress_every == 0 || step == n_steps)
            print_progress();
        }
      }
    {
      const Lap lap(output_time);
      if (history)
        history->flush();
      history.reset(); // closes history.csv
      if (solution_writer)
        solution_writer->finish(); // the last ParaView files
      // Several ranks: summary.json, written last, follows every rank's
      // pieces.
      wait_for_all_ranks();
    }

    // summary.json holds the figures a user compares between runs: peaks,
    // duration, their errors against the analytic reference, cost and the
    // energy error. Penalty contact chatters, so it also gives the peaks of
    // the force and pressure filtered with a centred moving average over
    // Output/Filter window. It is written last; a run stopped by the
    // stability monitor gets one too, with "status": "unstable", the reason,
    // and the figures of the steps before the instability.
    // Several ranks: the summary's displacement probes read the whole
    // state, which rank 0 receives here.
    for (auto *body : scene.body_pointers())
      body->gather_state();
    RunFacts facts;
    // What each rank lost waiting for the others' messages.
    if (n_ranks > 1)
      facts.seconds_waiting_per_rank =
        Utilities::MPI::gather(MPI_COMM_WORLD,
                               UnknownExchange::seconds_waiting());
    facts.seconds_in_passes_per_rank =
      n_ranks > 1 ?
        Utilities::MPI::gather(MPI_COMM_WORLD, integrator->time_in_passes()) :
        std::vector<double>{integrator->time_in_passes()};
    facts.time_step                = time_step;
    facts.stable                   = stable;
    facts.ranks_meet_at_every_step = integrator->ranks_meet_at_every_step();
    facts.n_steps                  = integrator->step_number();
    facts.wall_time                = wall_clock.wall_time();
    facts.setup_wall_time          = setup_time;
    facts.time_loop_wall_time      = loop_time;
    facts.initial_acceleration_wall_time = initial_acceleration_time;
    facts.output_wall_time               = output_time;
    facts.total_wall_time                = std::chrono::duration<double>(
                              std::chrono::steady_clock::now() - start_of_run)
                              .count();
    if (const auto *boundary = integrator->quasi_static_boundary())
      {
        facts.boundary_solve      = boundary->work();
        facts.n_massless_unknowns = boundary->n_unknowns();
      }
    if (!failure.empty())
      {
        facts.status      = "unstable";
        facts.stop_reason = unstable_message(failure);
      }
    if (is_root)
      {
        summary->write_json(parameters.output_directory + "/summary.json",
                            parameters,
                            parameter_file,
                            scene,
                            facts);
        RunSummary::write_pass_times(parameters.output_directory +
                                       "/pass_times.csv",
                                     scene);
        if (parameters.step_times)
          RunSummary::write_step_times(parameters.output_directory +
                                         "/step_times.csv",
                                       step_ends,
                                       passes_until,
                                       time_step);
      }
    if (!failure.empty())
      {
        if (is_root)
          std::cerr << "isoimpact: error in " << parameter_file << ": "
                    << facts.stop_reason << std::endl;
        return 1;
      }

    pcout << "  peak contact force " << summary->peak_force()
          << " N/m at t = " << summary->time_of_peak_force() << " s";
    if (scene.reference)
      pcout << " (analytic " << scene.reference->peak_force() << " N/m at "
            << scene.reference->time_of_peak() << " s)";
    if (!summary->contact_ended())
      pcout
        << "\n  warning: the bodies are still in contact at the end time "
        << parameters.end_time << " s: contact_duration_s in summary.json ("
        << summary->contact_duration()
        << " s) is the contact time so far, not the duration (contact_ended "
           "= false); raise 'Time integration/End time' to see the "
           "separation";
    pcout
      << "\n  max energy error " << 100. * summary->max_energy_error() << " %\n"
      << "  results: " << parameters.output_directory
      << "/{history.csv,summary.json,solution.pvd,contact_pressure_*.csv"
      << (std::any_of(scene.bodies.begin(),
                      scene.bodies.end(),
                      [](const auto &body) {
                        return !body->exchange().pass_time_history().empty();
                      }) ?
            ",pass_times.csv" :
            "")
      << (parameters.step_times ? ",step_times.csv" : "") << "}" << std::endl;
    pcout << "  wall time: set-up " << setup_time << " s, time steps "
          << loop_time << " s, output " << output_time << " s (ParaView "
          << paraview_time << " s), total " << facts.total_wall_time
          << " s (summary.json: wall_time_parts_s)" << std::endl;
    if (n_ranks > 1 && is_root)
      {
        std::cout << "  waits for the other ranks' messages:";
        for (unsigned int p = 0; p < n_ranks; ++p)
          std::cout << (p == 0 ? " " : ", ") << "rank " << p << ' '
                    << facts.seconds_waiting_per_rank[p] << " s";
        std::cout << " (summary.json: mpi_wait_s_per_rank)" << std::endl;
      }
    return 0;
  }
} // namespace isoimpact



// @sect3{The <code>main</code> function}
//
// Command line: a parameter file, or --help, or --print-parameters. Every
// error ends the program with a message on stderr and a non-zero exit code:
// 2 for bad input, 1 for a failure during the run.
int
main(int argc, char **argv)
{
  using namespace isoimpact;
  const std::string usage =
    "usage: isoimpact FILE.prm        run the scene described by FILE.prm\n"
    "       isoimpact --print-parameters  print a documented default file\n"
    "       isoimpact --help\n";
  if (argc != 2)
    {
      std::cerr << usage;
      return 2;
    }
  const std::string argument = argv[1];
  if (argument == "--help" || argument == "-h")
    {
      std::cout << usage
                << "\nThe parameter file has the subsections Body 1, Body 2 "
                   "(geometry, material, initial velocity), Model, "
                   "Discretization, Mass matrix, Contact, Obstacle (a rigid "
                   "plane or cylinder instead of Body 2), Time integration "
                   "and Output; see --print-parameters and doc/parameters.md."
                << std::endl;
      return 0;
    }
  if (argument == "--print-parameters")
    {
      // Into a full device the write fails: say so, with exit 1.
      try
        {
          print_default_parameters(std::cout);
          std::cout.flush();
        }
      catch (...)
        {
          std::cout.setstate(std::ios::badbit);
        }
      if (!std::cout)
        {
          std::cerr << "isoimpact: error: writing the default parameters "
                       "to the standard output failed (is the disk full?)"
                    << std::endl;
          return 1;
        }
      return 0;
    }

  // MPI: started by mpirun, every rank builds the scene and computes its
  // share of every step; without mpirun there is one rank. The threads per
  // rank are deal.II's choice (the cores over the ranks on the node) or
  // DEAL_II_NUM_THREADS.
  // Without a launcher the program does not initialise MPI at all: that
  // costs 0.36 s of every run on this machine, and deal.II's MPI
  // utilities answer "one rank" without it. The launchers say the number
  // of ranks in the environment (Open MPI, and PMI for MPICH and Slurm).
  std::optional<Utilities::MPI::MPI_InitFinalize> mpi;
  if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"))
    mpi.emplace(argc, argv, numbers::invalid_unsigned_int);
  const bool is_root  = world_rank() == 0;
  const bool parallel = n_world_ranks() > 1;
  // An error found on one rank alone leaves the others waiting for it:
  // stop them all (bad input is found by every rank alike, and they all
  // return 2).
  const auto stop_all = [&](const int code) {
    if (parallel)
      MPI_Abort(MPI_COMM_WORLD, code);
    return code;
  };
  try
    {
      const Parameters parameters = read_parameters(argument);
      ImpactProgram    program(parameters, argument);
      return program.run();
    }
  catch (const InputError &e)
    {
      if (is_root)
        std::cerr << "isoimpact: error: " << e.what() << std::endl;
      return 2;
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::cerr << "isoimpact: error in " << argument << ": ";
      e.print_info(std::cerr);
      std::cerr << std::endl;
      return stop_all(1);
    }
  catch (const std::exception &e)
    {
      std::cerr << "isoimpact: error in " << argument << ": " << e.what()
                << std::endl;
      return stop_all(1);
    }
  return 0;
}
