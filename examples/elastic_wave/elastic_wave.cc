// An example of a user's program on top of isoimpact: a standing elastic
// wave in a square block (FE_Q(2), HRZ mass, central differences), with the
// energy balance. Exits non-zero if the energy drifts by more than 1e-3.
#include <isoimpact/discretization/discretization.h>
#include <isoimpact/time_integration/central_difference.h>

#include <cmath>
#include <iostream>

using namespace dealii;

int
main()
{
  using namespace isoimpact;
  BodyGeometry geometry;
  geometry.shape              = BodyGeometry::Shape::rectangle;
  geometry.lower_left         = Point<2>(0., 0.);
  geometry.upper_right        = Point<2>(1., 1.);
  geometry.global_refinements = 3;

  ElasticMaterial material; // E = 1000 Pa, nu = 0.2, rho = 1 kg/m^3
  ElasticBody<2>  body("block",
                      create_discretization<2>(DiscretizationMethod::fea,
                                               geometry,
                                               2),
                      material,
                      MassScheme::hrz,
                      {},
                      Tensor<1, 2>());

  // Initial velocity v_x = sin(pi y): a shear wave between the free faces.
  for (types::global_dof_index i = 0; i < body.n_dofs(); ++i)
    if (body.discretization().dof_component(i) == 0)
      body.velocity(i) =
        std::sin(M_PI * body.discretization().dof_position(i)[1]);

  const double         dt = 0.5 * body.estimate_critical_time_step();
  CentralDifference<2> integrator({&body}, {}, dt);
  integrator.initialize();
  const double initial = integrator.energy_balance().total();
  double       drift   = 0.;
  for (unsigned int step = 1; step <= 400; ++step)
    {
      integrator.advance();
      drift = std::max(drift,
                       std::abs(integrator.energy_balance().total() - initial) /
                         initial);
    }
  std::cout << "elastic_wave: " << body.n_dofs() << " unknowns, dt = " << dt
            << " s, 400 steps, energy " << initial
            << " J/m, max relative energy drift " << drift << std::endl;
  return drift < 1e-3 ? 0 : 1;
}
