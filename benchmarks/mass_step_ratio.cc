// Cost of a step with one mass scheme against a step with another, both in
// one process and timed alternately: a step of scene A, then a step of
// scene B, N times per round. The median of the pairs' ratios B / A is the
// figure that the machine's changes of speed move least: both steps of a
// pair meet the same state of the machine, which two separate processes
// (benchmark_step_cost, "consistent / HRZ (normalised)") do not. Each step
// is the one the program takes between ParaView outputs, with the kinetic
// energy the stability monitor reads after it. The fastest round of each
// scene is printed beside. The last line, "RESULT key=value ...", is read by
// benchmarks/step_cost_sweep.py.
// Usage: benchmark_mass_step_ratio A.prm B.prm [n_steps] [rounds]
#include <deal.II/base/timer.h>

#include <isoimpact/scene/scene.h>

#include <algorithm>
#include <iostream>
#include <limits>
#include <memory>
#include <vector>

using namespace dealii;

int
main(int argc, char **argv)
{
  using namespace isoimpact;
  if (argc < 3)
    {
      std::cerr << "usage: benchmark_mass_step_ratio A.prm B.prm [n_steps] "
                   "[rounds]\n";
      return 2;
    }
  const unsigned int n_steps = argc > 3 ? std::stoi(argv[3]) : 200;
  const unsigned int rounds  = argc > 4 ? std::stoi(argv[4]) : 3;
  try
    {
      struct Run
      {
        Parameters                            parameters;
        Scene                                 scene;
        std::unique_ptr<CentralDifference<2>> integrator;
        double fastest_round      = std::numeric_limits<double>::infinity();
        double kinetic_energy_sum = 0.; // printed: not optimised out
      };
      std::vector<std::unique_ptr<Run>> runs;
      for (const char *file : {argv[1], argv[2]})
        {
          auto run        = std::make_unique<Run>();
          run->parameters = read_parameters(file);
          run->scene      = build_scene(run->parameters);
          run->integrator =
            std::make_unique<CentralDifference<2>>(run->scene.body_pointers(),
                                                   run->scene.interactions,
                                                   run->parameters.time_step);
          run->integrator->initialize();
          runs.push_back(std::move(run));
        }

      Timer               timer;
      std::vector<double> ratios;
      for (unsigned int round = 0; round < rounds; ++round)
        {
          double round_time[2] = {0., 0.};
          for (unsigned int step = 0; step < n_steps; ++step)
            {
              double one_step[2];
              for (unsigned int r = 0; r < 2; ++r)
                {
                  timer.restart();
                  runs[r]->integrator->advance(false, false);
                  runs[r]->kinetic_energy_sum +=
                    runs[r]->integrator->kinetic_energy();
                  one_step[r] = timer.wall_time();
                  round_time[r] += one_step[r];
                }
              ratios.push_back(one_step[1] / one_step[0]);
            }
          for (unsigned int r = 0; r < 2; ++r)
            runs[r]->fastest_round =
              std::min(runs[r]->fastest_round, round_time[r] / n_steps);
        }
      std::sort(ratios.begin(), ratios.end());
      const std::size_t n_pairs = ratios.size();
      const double      paired_ratio =
        n_pairs % 2 == 1 ?
               ratios[n_pairs / 2] :
               0.5 * (ratios[n_pairs / 2 - 1] + ratios[n_pairs / 2]);

      // Whether the bodies of a run are in contact at its end (a scene
      // without contact: no).
      const auto contact_on = [](const Run &run) {
        const auto &results = run.integrator->contact_results();
        return !results.empty() && results[0].n_active_points > 0;
      };
      for (unsigned int r = 0; r < 2; ++r)
        {
          const auto  &run = *runs[r];
          const double n   = run.scene.n_dofs();
          std::cout << (r == 0 ? "A " : "B ") << argv[1 + r] << ": "
                    << run.scene.n_dofs() << " unknowns, mass "
                    << to_string(run.parameters.mass_scheme) << ", contact "
                    << (contact_on(run) ? "on" : "OFF")
                    << " at the end (t = " << run.integrator->time()
                    << " s), step " << 1e9 * run.fastest_round / n
                    << " ns per unknown (fastest round), mean kinetic energy "
                    << run.kinetic_energy_sum / (rounds * n_steps) << " J/m\n";
        }
      std::cout << "B / A: " << paired_ratio << " (median of " << n_pairs
                << " pairs), "
                << runs[1]->fastest_round / runs[0]->fastest_round
                << " (fastest rounds)\n";
      std::cout << "RESULT paired_ratio=" << paired_ratio << " fastest_ratio="
                << runs[1]->fastest_round / runs[0]->fastest_round
                << " contact="
                << (contact_on(*runs[0]) && contact_on(*runs[1]) ? 1 : 0)
                << std::endl;
    }
  catch (const std::exception &e)
    {
      std::cerr << "benchmark_mass_step_ratio: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
