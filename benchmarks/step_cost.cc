// Cost of one explicit step against a bare sparse matrix-vector product of
// the same stiffness matrices, measured in the same run (the honest figure on
// a shared machine), and where the step spends the rest: the acceleration
// (ElasticBody::compute_acceleration, with the mass solve) against contact
// and the integrator's vector updates. Each figure is the fastest of
// `rounds` interleaved rounds of n_steps steps (resp. products), so that a
// busy neighbour on the machine inflates no figure more than the others;
// the step and the mat-vec are also timed in pairs (a step, then the
// product), and the median of the pairs' ratios is reported beside.
// The step is the one the program takes between ParaView outputs (no
// contact points recorded, the whole-step velocity not formed), with the
// kinetic energy that the program's stability monitor reads after every
// step; the output step (both) is timed apart, n_steps / 4 per round, the
// fastest round.
// Memory: the peak resident set of the process (VmHWM) and, for consistent
// mass, the Cholesky factors. The last line, "RESULT key=value ...", is read
// by benchmarks/step_cost_sweep.py.
// Usage: benchmark_step_cost FILE.prm [n_steps] [rounds]
#include <deal.II/base/timer.h>

#include <isoimpact/scene/scene.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

using namespace dealii;

namespace
{
  // A line "Key:  1234 kB" of /proc/self/status, in bytes (0 if absent).
  double
  status_bytes(const std::string &key)
  {
    std::ifstream status("/proc/self/status");
    std::string   line;
    while (std::getline(status, line))
      if (line.rfind(key + ":", 0) == 0)
        {
          std::istringstream values(line.substr(key.size() + 1));
          double             kilobytes = 0.;
          values >> kilobytes;
          return 1024. * kilobytes;
        }
    return 0.;
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace isoimpact;
  if (argc < 2)
    {
      std::cerr << "usage: benchmark_step_cost FILE.prm [n_steps] [rounds]\n";
      return 2;
    }
  const unsigned int n_steps        = argc > 2 ? std::stoi(argv[2]) : 200;
  const unsigned int rounds         = argc > 3 ? std::stoi(argv[3]) : 3;
  const unsigned int n_output_steps = std::max(1U, n_steps / 4);
  try
    {
      Timer                setup_timer;
      const Parameters     parameters = read_parameters(argv[1]);
      Scene                scene      = build_scene(parameters);
      const double         setup_time = setup_timer.wall_time();
      CentralDifference<2> integrator(scene.body_pointers(),
                                      scene.interactions,
                                      parameters.time_step);
      integrator.initialize();

      std::vector<Vector<double>> forces, products;
      for (const auto &body : scene.bodies)
        {
          forces.emplace_back(body->n_dofs());
          products.emplace_back(body->n_dofs());
        }
      // Each contact model's view of the bodies (forces into scratch).
      // (The displacements' views are taken at each evaluation: a body's
      // step may swap in a displacement formed in its pass.)
      std::vector<std::vector<unsigned int>>           contact_bodies;
      std::vector<std::vector<const Vector<double> *>> contact_velocities;
      std::vector<std::vector<Vector<double> *>>       contact_forces;
      for (const auto &interaction : scene.interactions)
        {
          std::vector<unsigned int> body_indices = {interaction.first_body};
          if (interaction.contact->n_bodies() == 2)
            body_indices.push_back(interaction.second_body);
          contact_bodies.push_back(body_indices);
          contact_velocities.emplace_back();
          contact_forces.emplace_back();
          for (const unsigned int b : body_indices)
            {
              contact_velocities.back().push_back(&scene.bodies[b]->velocity);
              contact_forces.back().push_back(&forces[b]);
            }
        }
      const auto contact_views = [&](const unsigned int c) {
        std::vector<ArrayView<const double>> views;
        for (const unsigned int b : contact_bodies[c])
          views.push_back(scene.bodies[b]->contact_displacement());
        return views;
      };
      const double infinity         = std::numeric_limits<double>::infinity();
      double       step_time        = infinity;
      double       matvec           = infinity;
      double       accel_time       = infinity;
      double       solve_time       = infinity;
      double       output_step_time = infinity;
      double       contact_time     = infinity;
      Timer        timer;
      // Each step is followed by the mat-vec it is compared with, so that
      // a change of the machine's load hits both alike: the median of these
      // paired ratios is the figure that noise moves least.
      std::vector<double> paired_ratios;
      double              kinetic_energy_sum = 0.; // printed: not optimised out
      for (unsigned int round = 0; round < rounds; ++round)
        {
          double round_steps = 0., round_matvecs = 0., round_contacts = 0.;
          for (unsigned int step = 0; step < n_steps; ++step)
            {
              timer.restart();
              integrator.advance(false, false);
              kinetic_energy_sum += integrator.kinetic_energy();
              const double one_step = timer.wall_time();
              timer.restart();
              for (unsigned int b = 0; b < scene.bodies.size(); ++b)
                scene.bodies[b]->stiffness_matrix().vmult(
                  products[b],
                  scene.bodies[b]->displacement);
              const double one_matvec = timer.wall_time();
              timer.restart();
              for (unsigned int c = 0; c < scene.interactions.size(); ++c)
                scene.interactions[c].contact->evaluate(contact_views(c),
                                                        contact_velocities[c],
                                                        contact_forces[c],
                                                        false);
              round_contacts += timer.wall_time();
              round_steps += one_step;
              round_matvecs += one_matvec;
              paired_ratios.push_back(one_step / one_matvec);
            }
          step_time    = std::min(step_time, round_steps / n_steps);
          matvec       = std::min(matvec, round_matvecs / n_steps);
          contact_time = std::min(contact_time, round_contacts / n_steps);

          // The output step (contact points and the whole-step state), a
          // quarter as many, so that the rounds stay inside the impact.
          timer.restart();
          for (unsigned int step = 0; step < n_output_steps; ++step)
            {
              integrator.advance(true, true);
              kinetic_energy_sum += integrator.kinetic_energy();
            }
          output_step_time =
            std::min(output_step_time, timer.wall_time() / n_output_steps);

          // The acceleration alone (no contact force): condensation, K u,
          // mass solve, distribution.
          timer.restart();
          for (unsigned int step = 0; step < n_steps; ++step)
            for (unsigned int b = 0; b < scene.bodies.size(); ++b)
              {
                forces[b] = 0.;
                scene.bodies[b]->compute_acceleration(
                  scene.bodies[b]->displacement,
                  forces[b],
                  products[b]);
              }
          accel_time = std::min(accel_time, timer.wall_time() / n_steps);

          // The consistent mass solve alone.
          timer.restart();
          for (unsigned int step = 0; step < n_steps; ++step)
            for (unsigned int b = 0; b < scene.bodies.size(); ++b)
              if (const auto *solver =
                    scene.bodies[b]->consistent_mass_solver())
                solver->solve(products[b], scene.bodies[b]->velocity);
          solve_time = std::min(solve_time, timer.wall_time() / n_steps);
        }

      std::sort(paired_ratios.begin(), paired_ratios.end());
      const std::size_t n_pairs = paired_ratios.size();
      const double      paired_ratio =
        n_pairs % 2 == 1 ?
               paired_ratios[n_pairs / 2] :
               0.5 * (paired_ratios[n_pairs / 2 - 1] + paired_ratios[n_pairs / 2]);

      std::size_t nonzeros = 0, factor_nonzeros = 0, factor_bytes = 0,
                  factor_entries = 0;
      unsigned int n_factors = 0, n_subtrees = 0;
      double       factor_setup = 0.;
      for (const auto &body : scene.bodies)
        {
          nonzeros += body->stiffness_matrix().n_nonzero_elements();
          if (const auto *solver = body->consistent_mass_solver())
            {
              factor_nonzeros += solver->factor_nonzeros();
              factor_entries += solver->factor_stored_entries();
              n_factors += solver->n_factors();
              n_subtrees += solver->n_parallel_subtrees();
              factor_bytes += solver->memory_consumption();
              factor_setup += solver->setup_time();
            }
        }
      const double n    = scene.n_dofs();
      const double peak = status_bytes("VmHWM");
      const bool   contact_on =
        !integrator.contact_results().empty() &&
        integrator.contact_results()[0].n_active_points > 0;

      std::cout << "unknowns " << scene.n_dofs() << ", stiffness nonzeros "
                << nonzeros << " (" << nonzeros / n << " per row), mass "
                << to_string(parameters.mass_scheme) << ", " << rounds
                << " rounds of " << n_steps << " steps, contact "
                << (contact_on ? "on" : "OFF")
                << " at the end (t = " << integrator.time()
                << " s), mean kinetic energy of the steps timed "
                << kinetic_energy_sum / (rounds * (n_steps + n_output_steps))
                << " J/m\n"
                << "set-up (scene)       " << setup_time << " s\n";
      if (factor_nonzeros > 0)
        std::cout << "mass factorisation   " << factor_setup << " s, "
                  << factor_nonzeros << " nonzeros (" << factor_nonzeros / n
                  << " per unknown; " << factor_entries / n << " stored), "
                  << factor_bytes / n << " bytes per unknown, " << n_factors
                  << " factors, " << n_subtrees
                  << " subtrees solved side by side\n"
                  << "mass solve alone     " << 1e3 * solve_time << " ms ("
                  << 1e9 * solve_time / n << " ns per unknown)\n";
      std::cout << "peak memory (VmHWM)  " << peak / n << " bytes per unknown\n"
                << "time per step        " << 1e3 * step_time << " ms ("
                << 1e9 * step_time / n << " ns per unknown)\n"
                << "output step          " << 1e3 * output_step_time << " ms ("
                << 1e9 * output_step_time / n << " ns per unknown)\n"
                << "acceleration alone   " << 1e3 * accel_time << " ms ("
                << 1e9 * accel_time / n << " ns per unknown)\n"
                << "contact alone        " << 1e3 * contact_time
                << " ms (after each mat-vec, " << scene.interactions.size()
                << " interaction(s))\n"
                << "bare mat-vec (all K) " << 1e3 * matvec << " ms ("
                << 1e9 * matvec / n << " ns per unknown)\n"
                << "step / mat-vec       " << step_time / matvec
                << " (fastest rounds), " << paired_ratio << " (median of "
                << paired_ratios.size() << " step/mat-vec pairs)" << std::endl;
      std::cout << "RESULT unknowns=" << scene.n_dofs()
                << " mass=" << to_string(parameters.mass_scheme)
                << " contact=" << (contact_on ? 1 : 0)
                << " step_ns=" << 1e9 * step_time / n
                << " output_step_ns=" << 1e9 * output_step_time / n
                << " accel_ns=" << 1e9 * accel_time / n
                << " contact_us=" << 1e6 * contact_time << " solve_ns="
                << (factor_nonzeros > 0 ? 1e9 * solve_time / n : 0.)
                << " matvec_ns=" << 1e9 * matvec / n
                << " paired_ratio=" << paired_ratio
                << " peak_bytes=" << peak / n
                << " factor_bytes=" << factor_bytes / n
                << " factor_nnz=" << factor_nonzeros / n
                << " factor_entries=" << factor_entries / n
                << " factors=" << n_factors << " subtrees=" << n_subtrees
                << " factor_setup_s=" << factor_setup
                << " setup_s=" << setup_time << std::endl;
    }
  catch (const std::exception &e)
    {
      std::cerr << "benchmark_step_cost: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
