// Cost of one explicit step against a bare sparse matrix-vector product of
// the same stiffness matrices, measured in the same run (the honest figure on
// a shared machine). Usage: benchmark_step_cost FILE.prm [n_steps]
#include <deal.II/base/timer.h>

#include <isoimpact/scene/scene.h>

#include <iostream>

using namespace dealii;

int
main(int argc, char **argv)
{
  using namespace isoimpact;
  if (argc < 2)
    {
      std::cerr << "usage: benchmark_step_cost FILE.prm [n_steps]\n";
      return 2;
    }
  const unsigned int n_steps = argc > 2 ? std::stoi(argv[2]) : 200;
  try
    {
      const Parameters     parameters = read_parameters(argv[1]);
      Scene                scene      = build_scene(parameters);
      CentralDifference<2> integrator(scene.body_pointers(),
                                      scene.interactions,
                                      parameters.time_step);
      integrator.initialize();

      Timer timer;
      for (unsigned int step = 0; step < n_steps; ++step)
        integrator.advance();
      const double step_time = timer.wall_time() / n_steps;

      std::size_t nonzeros = 0;
      timer.restart();
      for (unsigned int step = 0; step < n_steps; ++step)
        for (const auto &body : scene.bodies)
          body->stiffness_matrix().vmult(body->acceleration,
                                         body->displacement);
      const double matvec_time = timer.wall_time() / n_steps;
      for (const auto &body : scene.bodies)
        nonzeros += body->stiffness_matrix().n_nonzero_elements();

      const double n = scene.n_dofs();
      std::cout << "unknowns " << scene.n_dofs() << ", stiffness nonzeros "
                << nonzeros << " (" << nonzeros / n << " per row), mass "
                << to_string(parameters.mass_scheme) << ", " << n_steps
                << " steps\n"
                << "time per step        " << 1e3 * step_time << " ms ("
                << 1e9 * step_time / n << " ns per unknown)\n"
                << "bare mat-vec (all K) " << 1e3 * matvec_time << " ms ("
                << 1e9 * matvec_time / n << " ns per unknown)\n"
                << "step / mat-vec       " << step_time / matvec_time
                << std::endl;
    }
  catch (const std::exception &e)
    {
      std::cerr << "benchmark_step_cost: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
