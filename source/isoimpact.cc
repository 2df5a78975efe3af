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
 * consistent. The scheme is stable for time steps below 2/omega_max; the
 * program estimates that limit and prints it.
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
 */

// @sect3{Include files}
//
// deal.II's utilities for timing and parallel-ready output streams, and the
// library's layers: the scene (layer 6) pulls in the time integrator (5),
// the mechanics (4) and the discretisations (3).
#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <isoimpact/scene/output.h>
#include <isoimpact/scene/parameters.h>
#include <isoimpact/scene/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  // @sect3{The <code>ImpactProgram</code> class}
  //
  // As in step-48, the class holds the pieces of one explicit dynamics run:
  // the scene (bodies, contact, reference), the time integrator, and the
  // output. Peak values for the summary are collected along the way.
  class ImpactProgram
  {
  public:
    ImpactProgram(const Parameters  &parameters,
                  const std::string &parameter_file);
    void
    run();

  private:
    void
    print_setup();
    void
    open_output();
    void
    record(const bool write_solution, const bool write_profile);
    void
    write_pressure_profile();
    std::string
    unstable_message() const;
    void
    print_progress();
    void
    write_summary();

    const Parameters  parameters;
    const std::string parameter_file;

    ConditionalOStream pcout;
    TimerOutput        timer;

    Scene                                 scene;
    std::unique_ptr<CentralDifference<2>> integrator;
    std::unique_ptr<SolutionWriter>       solution_writer;
    std::ofstream                         history;
    double                                critical_time_step = 0.;
    unsigned int                          n_steps            = 0;
    unsigned int                          next_profile       = 0;

    // Running figures for the summary.
    double initial_energy       = 0.;
    double max_energy_error     = 0.;
    double peak_force           = 0.;
    double time_of_peak         = 0.;
    double peak_pressure        = 0.;
    double first_contact        = -1.;
    double last_contact         = -1.;
    double current_force        = 0.;
    double current_pressure     = 0.;
    double current_energy_error = 0.;
    Timer  wall_clock;
    // Every step's contact force and maximal pressure, for the filtered
    // peaks of the summary.
    std::vector<double> force_history, pressure_history;
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
    , pcout(std::cout, true)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
  {}



  void
  ImpactProgram::print_setup()
  {
    pcout << "isoimpact: " << parameter_file << '\n';
    for (const auto &body : scene.bodies)
      pcout << "  " << body->name() << ": " << body->discretization().name()
            << ", "
            << body->discretization().get_triangulation().n_active_cells()
            << " cells, " << body->n_dofs() << " unknowns, mass "
            << body->total_mass() << " kg/m (" << to_string(body->mass_scheme())
            << ")\n";
    pcout << "  contact: " << scene.contacts[0]->description() << '\n';
    if (parameters.obstacle.active())
      pcout << "  scene reduction: Body 1 against a rigid obstacle; Body 2 "
               "is ignored\n";
    if (scene.symmetry_factor != 1.)
      pcout << "  symmetry: half of each body is modelled; contact force "
               "and energies are reported for the full bodies (factor "
            << scene.symmetry_factor << ")\n";
    pcout << "  time step " << parameters.time_step
          << " s; estimated critical step without contact "
          << critical_time_step << " s (ratio "
          << parameters.time_step / critical_time_step << ")\n";
    if (parameters.time_step > critical_time_step)
      pcout << "  warning: the time step exceeds the estimated critical step; "
               "the run is likely to become unstable\n";
    pcout << "  " << n_steps << " steps to t = " << parameters.end_time
          << " s; output in " << parameters.output_directory << std::endl;
  }



  // @sect3{Output files}
  //
  // The output directory is created only once the scene is built, so that a
  // bad parameter file leaves nothing behind. history.csv gets one row per
  // output step; its header says the unit of every column.
  void
  ImpactProgram::open_output()
  {
    const std::string &directory = parameters.output_directory;
    std::filesystem::create_directories(directory);
    std::filesystem::copy_file(
      parameter_file,
      directory + "/parameters.prm",
      std::filesystem::copy_options::overwrite_existing);
    solution_writer =
      std::make_unique<SolutionWriter>(directory, parameters.vtu_subdivisions);

    history.open(directory + "/history.csv");
    history << "# isoimpact history of " << parameter_file << "\n"
            << "# units: time [s], contact_force [N/m] (resultant on body 1 "
               "along the line of impact, per unit thickness, full bodies), "
               "max_contact_pressure [Pa], energies [J/m] (per unit "
               "thickness, full bodies), analytic columns: quasi-static "
               "Hertz impact ("
            << parameters.approach_law << ")\n";
    if (parameters.obstacle.active())
      history << "# scene: body 1 against a "
              << scene.contacts[0]->description()
              << "; energies are those of body 1 (the obstacle stores "
                 "none)\n";
    if (scene.symmetry_factor != 1.)
      history << "# the model is a half by symmetry: contact_force and "
                 "energies are those of the model times "
              << scene.symmetry_factor << "\n";
    history << "time,contact_force,max_contact_pressure,kinetic_energy,"
               "strain_energy,contact_energy,total_energy";
    if (scene.reference)
      history << ",analytic_contact_force,analytic_max_contact_pressure";
    history << '\n' << std::setprecision(10);
  }



  // @sect3{Recording a step}
  //
  // The contact force is the resultant of the contact tractions on body 1,
  // projected on the line of impact; with a half model it is doubled to give
  // the force between the full cylinders, as the analytic reference does.
  // A non-finite energy means that the explicit scheme became unstable: the
  // run stops with an error rather than printing NaN.
  void
  ImpactProgram::record(const bool write_solution, const bool write_profile)
  {
    const double t      = integrator->time();
    const auto  &result = integrator->contact_results()[0];
    const double factor = scene.symmetry_factor;

    AssertThrow(std::isfinite(result.force_on_body_0.norm()),
                ExcMessage(unstable_message()));
    current_force = factor * (result.force_on_body_0 * scene.impact_direction);
    current_pressure = result.max_pressure;
    if (current_force > peak_force)
      {
        peak_force   = current_force;
        time_of_peak = t;
      }
    peak_pressure = std::max(peak_pressure, current_pressure);
    force_history.push_back(current_force);
    pressure_history.push_back(current_pressure);
    if (result.n_active_points > 0)
      {
        if (first_contact < 0.)
          first_contact = t;
        last_contact = t;
      }

    if (integrator->step_number() % parameters.history_interval == 0)
      {
        // The energy balance costs two matrix-vector products: only at
        // history steps.
        const EnergyBalance energy = integrator->energy_balance();
        const double        total  = factor * energy.total();
        AssertThrow(std::isfinite(total), ExcMessage(unstable_message()));
        if (integrator->step_number() == 0)
          initial_energy = total;
        current_energy_error =
          std::abs(total - initial_energy) / initial_energy;
        max_energy_error = std::max(max_energy_error, current_energy_error);

        history << t << ',' << current_force << ',' << current_pressure << ','
                << factor * energy.kinetic << ',' << factor * energy.strain
                << ',' << factor * energy.contact << ',' << total;
        if (scene.reference)
          history << ',' << scene.reference->contact_force(t) << ','
                  << scene.reference->max_contact_pressure(t);
        history << '\n';
      }

    if (write_solution)
      {
        TimerOutput::Scope scope(timer, "output: ParaView");
        solution_writer->write(scene.body_pointers(), t);
      }
    if (write_profile)
      write_pressure_profile();
  }



  // The pressure along the contact surface at a requested time: one row per
  // Gauss point in contact, with its position across the line of impact and
  // the Hertz profile of the analytic force at that time.
  std::string
  ImpactProgram::unstable_message() const
  {
    return "the solution became non-finite at step " +
           std::to_string(integrator->step_number()) +
           " (t = " + std::to_string(integrator->time()) +
           " s): the time step " + std::to_string(parameters.time_step) +
           " s is probably above the critical step (estimated " +
           std::to_string(critical_time_step) +
           " s without contact; penalty contact lowers it further)";
  }



  void
  ImpactProgram::write_pressure_profile()
  {
    const double t      = integrator->time();
    auto         points = integrator->contact_results()[0].points;
    Tensor<1, 2> across;
    across[0] = scene.impact_direction[1];
    across[1] = -scene.impact_direction[0];
    std::sort(points.begin(), points.end(), [&](const auto &a, const auto &b) {
      return a.reference_position * across < b.reference_position * across;
    });

    std::ostringstream name;
    name << parameters.output_directory << "/contact_pressure_t" << std::fixed
         << std::setprecision(4) << t << ".csv";
    std::ofstream out(name.str());
    out << "# contact pressure along the contact surface at t = " << t
        << " s\n# units: position [m] (reference position across the line "
           "of impact), pressure [Pa]; surface: 1 or 2 (the body whose "
           "Gauss point it is)\nposition,pressure,surface";
    const double force =
      scene.reference ? scene.reference->contact_force(t) : 0.;
    if (scene.reference)
      out << ",analytic_pressure";
    out << '\n' << std::setprecision(10);
    for (const auto &point : points)
      {
        const double s = point.reference_position * across;
        out << s << ',' << point.pressure << ',' << point.body + 1;
        if (scene.reference)
          out << ',' << scene.reference->pressure(force, s);
        out << '\n';
      }
  }



  void
  ImpactProgram::print_progress()
  {
    const double elapsed = wall_clock.wall_time();
    const double done    = double(integrator->step_number()) / n_steps;
    pcout << "  step " << std::setw(6) << integrator->step_number() << "/"
          << n_steps << "  t = " << std::fixed << std::setprecision(4)
          << integrator->time() << " s  contact force = " << std::setw(9)
          << std::setprecision(2) << current_force
          << " N/m  energy error = " << std::setprecision(3)
          << 100. * current_energy_error << " %  elapsed "
          << std::setprecision(1) << elapsed << " s, left ~"
          << elapsed * (1. - done) / std::max(done, 1e-12) << " s"
          << std::defaultfloat << std::setprecision(6) << std::endl;
  }



  // @sect3{The summary}
  //
  // summary.json holds the figures a user compares between runs: peaks,
  // duration, their errors against the analytic reference, cost and the
  // energy error. It is written last, to a temporary file renamed at the
  // end, so a run that fails leaves no summary.
  //
  // Penalty contact in explicit dynamics chatters: the raw force and, more
  // so, the pointwise maximal pressure carry oscillations at the period of a
  // few steps. As crash codes do with their contact force output, the summary
  // also gives peaks of the signals filtered with a centred moving average
  // over a fixed physical window (Output/Filter window). A filtered peak
  // finds the index of its maximum too.
  namespace
  {
    std::pair<double, unsigned int>
    filtered_peak(const std::vector<double> &signal, const unsigned int width)
    {
      const int half = width / 2, n = signal.size();
      double    best       = 0.;
      unsigned  best_index = 0;
      for (int i = 0; i < n; ++i)
        {
          double sum   = 0.;
          int    count = 0;
          for (int j = std::max(0, i - half); j <= std::min(n - 1, i + half);
               ++j)
            sum += signal[j], ++count;
          if (sum / count > best)
            best = sum / count, best_index = i;
        }
      return {best, best_index};
    }
  } // namespace

  void
  ImpactProgram::write_summary()
  {
    const double duration =
      (first_contact >= 0.) ? last_contact - first_contact : 0.;
    const unsigned int width =
      std::max(1u,
               static_cast<unsigned int>(
                 std::round(parameters.filter_window / parameters.time_step)));
    const auto   filtered_force    = filtered_peak(force_history, width);
    const auto   filtered_pressure = filtered_peak(pressure_history, width);
    const double filtered_time = filtered_force.second * parameters.time_step;
    const std::string path     = parameters.output_directory + "/summary.json";
    {
      std::ofstream out(path + ".tmp");
      out << std::setprecision(10) << "{\n"
          << "  \"parameter_file\": \"" << parameter_file << "\",\n"
          << "  \"discretization\": \""
          << scene.bodies[0]->discretization().name() << "\",\n"
          << "  \"mass_matrix\": \"" << to_string(parameters.mass_scheme)
          << "\",\n"
          << "  \"unknowns\": " << scene.n_dofs() << ",\n"
          << "  \"cells\": [";
      for (unsigned int b = 0; b < scene.bodies.size(); ++b)
        out << (b ? ", " : "")
            << scene.bodies[b]
                 ->discretization()
                 .get_triangulation()
                 .n_active_cells();
      out << "],\n"
          << "  \"vtu_subdivisions\": " << parameters.vtu_subdivisions << ",\n"
          << "  \"time_step_s\": " << parameters.time_step << ",\n"
          << "  \"critical_time_step_estimate_s\": " << critical_time_step
          << ",\n"
          << "  \"steps\": " << integrator->step_number() << ",\n"
          << "  \"wall_time_s\": " << wall_clock.wall_time() << ",\n"
          << "  \"symmetry_factor\": " << scene.symmetry_factor << ",\n"
          << "  \"obstacle\": \"" << parameters.obstacle.type << "\",\n"
          << "  \"peak_contact_force_N_per_m\": " << peak_force << ",\n"
          << "  \"time_of_peak_force_s\": " << time_of_peak << ",\n"
          << "  \"contact_duration_s\": " << duration << ",\n"
          << "  \"peak_contact_pressure_Pa\": " << peak_pressure << ",\n"
          << "  \"filter_window_s\": " << width * parameters.time_step << ",\n"
          << "  \"filtered_peak_contact_force_N_per_m\": "
          << filtered_force.first << ",\n"
          << "  \"time_of_filtered_peak_force_s\": " << filtered_time << ",\n"
          << "  \"filtered_peak_contact_pressure_Pa\": "
          << filtered_pressure.first << ",\n"
          << "  \"max_energy_error\": " << max_energy_error;
      // The displacement of each body's first unknown pair at the end: a
      // probe that the output tests compare with the ParaView files.
      out << ",\n  \"final_displacement_probe\": [";
      for (unsigned int b = 0; b < scene.bodies.size(); ++b)
        {
          const auto &body = *scene.bodies[b];
          const auto &disc = body.discretization();
          // The unknowns of component 0 and 1 at the same node.
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
          out << (b ? ", " : "") << "{\"body\": \"" << body.name()
              << "\", \"x_m\": " << p[0] << ", \"y_m\": " << p[1]
              << ", \"ux_m\": " << body.displacement(ix)
              << ", \"uy_m\": " << body.displacement(iy) << "}";
        }
      out << "]";
      if (scene.reference)
        {
          const auto &ref = *scene.reference;
          const auto  rel = [](const double value, const double reference) {
            return (value - reference) / reference;
          };
          out << ",\n  \"analytic\": {\"approach_law\": \""
              << parameters.approach_law
              << "\", \"peak_contact_force_N_per_m\": " << ref.peak_force()
              << ", \"time_of_peak_force_s\": " << ref.time_of_peak()
              << ", \"contact_duration_s\": " << ref.contact_duration()
              << ", \"peak_contact_pressure_Pa\": " << ref.peak_pressure()
              << "},\n  \"relative_error\": {\"peak_contact_force\": "
              << rel(peak_force, ref.peak_force())
              << ", \"time_of_peak_force\": "
              << rel(time_of_peak, ref.time_of_peak())
              << ", \"contact_duration\": "
              << rel(duration, ref.contact_duration())
              << ", \"peak_contact_pressure\": "
              << rel(peak_pressure, ref.peak_pressure())
              << ", \"filtered_peak_contact_force\": "
              << rel(filtered_force.first, ref.peak_force())
              << ", \"time_of_filtered_peak_force\": "
              << rel(filtered_time, ref.time_of_peak())
              << ", \"filtered_peak_contact_pressure\": "
              << rel(filtered_pressure.first, ref.peak_pressure()) << "}";
        }
      out << "\n}\n";
    }
    std::filesystem::rename(path + ".tmp", path);
  }



  // @sect3{The time loop}
  //
  // After set-up, the loop is short: advance one step, and at output steps
  // record the history, the ParaView files and the pressure profiles.
  void
  ImpactProgram::run()
  {
    {
      TimerOutput::Scope scope(timer, "set-up: meshes, matrices, contact");
      scene              = build_scene(parameters);
      critical_time_step = std::numeric_limits<double>::max();
      for (const auto &body : scene.bodies)
        critical_time_step =
          std::min(critical_time_step, body->estimate_critical_time_step());
      n_steps = static_cast<unsigned int>(
        std::ceil(parameters.end_time / parameters.time_step - 1e-9));
      integrator = std::make_unique<CentralDifference<2>>(scene.body_pointers(),
                                                          scene.interactions,
                                                          parameters.time_step);
    }
    print_setup();
    open_output();

    wall_clock.restart();
    const auto is_vtu_step = [&](const unsigned int step) {
      return parameters.vtu_interval > 0 &&
             (step % parameters.vtu_interval == 0 || step == n_steps);
    };
    // A profile is written at the first step at or after each requested time.
    const auto profile_due = [&]() {
      return next_profile < parameters.profile_times.size() &&
             integrator->time() >=
               parameters.profile_times[next_profile] - 1e-12;
    };

    integrator->initialize(true);
    record(is_vtu_step(0), false);
    const unsigned int progress_every =
      std::max(1u,
               static_cast<unsigned int>(n_steps *
                                         parameters.progress_interval / 100.));
    for (unsigned int step = 1; step <= n_steps; ++step)
      {
        const double next_time = step * parameters.time_step;
        const bool   profile =
          next_profile < parameters.profile_times.size() &&
          next_time >= parameters.profile_times[next_profile] - 1e-12;
        {
          TimerOutput::Scope scope(timer, "time steps");
          integrator->advance(profile);
        }
        {
          TimerOutput::Scope scope(timer, "output: history and profiles");
          record(is_vtu_step(step), profile_due());
          while (profile_due())
            ++next_profile;
        }
        if (step % progress_every == 0 || step == n_steps)
          print_progress();
      }
    history.close();
    write_summary();

    pcout << "  peak contact force " << peak_force
          << " N/m at t = " << time_of_peak << " s";
    if (scene.reference)
      pcout << " (analytic " << scene.reference->peak_force() << " N/m at "
            << scene.reference->time_of_peak() << " s)";
    pcout << "\n  max energy error " << 100. * max_energy_error << " %\n"
          << "  results: " << parameters.output_directory
          << "/{history.csv,summary.json,solution.pvd,contact_pressure_*.csv}"
          << std::endl;
    timer.print_summary();
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
      print_default_parameters(std::cout);
      return 0;
    }

  try
    {
      const Parameters parameters = read_parameters(argument);
      ImpactProgram    program(parameters, argument);
      program.run();
    }
  catch (const InputError &e)
    {
      std::cerr << "isoimpact: error: " << e.what() << std::endl;
      return 2;
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::cerr << "isoimpact: error in " << argument << ": ";
      e.print_info(std::cerr);
      std::cerr << std::endl;
      return 1;
    }
  catch (const std::exception &e)
    {
      std::cerr << "isoimpact: error in " << argument << ": " << e.what()
                << std::endl;
      return 1;
    }
  return 0;
}
