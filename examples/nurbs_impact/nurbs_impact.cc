// An isogeometric impact on top of isoimpact: two elastic cylinders (R = 4
// m, E = 1000 Pa, nu = 0.2, rho = 1 kg/m^3, plane strain) meet at 4 m/s as
// NURBS bodies (four quadratic patches with exact arcs each, HRZ mass) with
// the symmetric two-pass penalty contact and central differences. Writes the
// contact force to nurbs_impact_history.csv and exits non-zero unless the
// contact lasts as long as the analytic Hertz impact (0.749 s) to 2 %.
#include <isoimpact/discretization/discretization.h>
#include <isoimpact/scene/hertz_reference.h>
#include <isoimpact/time_integration/central_difference.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

using namespace dealii;

int
main()
{
  using namespace isoimpact;

  // @sect3{The bodies}
  //
  // The cylinders are centred at (0, 4) and (0, -4) and touch at the
  // origin. By symmetry only their halves x >= 0 are modelled, with a roller
  // (u_x = 0) on the cut. Body 1 moves down, body 2 up. Three global
  // refinements give 8 x 8 knot spans in each patch (256 elements per body).
  const ElasticMaterial material; // E = 1000 Pa, nu = 0.2, rho = 1 kg/m^3
  std::vector<std::unique_ptr<ElasticBody<2>>> bodies;
  for (const double side : {1., -1.})
    {
      BodyGeometry geometry; // a half disk of radius 4 m
      geometry.center             = Point<2>(0., 4. * side);
      geometry.global_refinements = 3;
      bodies.push_back(std::make_unique<ElasticBody<2>>(
        side > 0 ? "upper" : "lower",
        create_discretization<2>(DiscretizationMethod::iga, geometry, 2),
        material,
        MassScheme::hrz,
        std::vector<RollerCondition>{{BodyGeometry::symmetry_boundary_id, 0}},
        Tensor<1, 2>({0., -2. * side})));
    }

  // @sect3{Contact and time integration}
  //
  // Contact is searched on the arcs only, with the default settings:
  // eps_N = 1e5 Pa/m, half of it per pass, 4 Gauss points per boundary span.
  // The time step 5e-4 s is below the critical step of these meshes.
  const auto arc = [&](const unsigned int b) {
    return bodies[b]->discretization().boundary_segments(
      BodyGeometry::curved_boundary_id);
  };
  const PenaltyContact<2> contact(ContactSettings(), arc(0), arc(1));
  CentralDifference<2>    integrator({bodies[0].get(), bodies[1].get()},
                                  {{&contact, 0, 1}},
                                  5e-4);

  // @sect3{The time loop}
  //
  // The force on body 1 along the line of impact (y), doubled for the full
  // cylinders, is written at every step; contact lasts from the first to
  // the last step with active contact points.
  std::ofstream history("nurbs_impact_history.csv");
  history << "# contact force between the full cylinders per unit thickness\n"
          << "time_s,contact_force_N_per_m\n";
  double first_contact = -1., last_contact = -1.;
  integrator.initialize();
  while (integrator.time() < 0.9 - 1e-9)
    {
      integrator.advance();
      const auto &result = integrator.contact_results()[0];
      history << integrator.time() << ',' << 2. * result.force_on_body_0[1]
              << '\n';
      if (result.n_active_points > 0)
        {
          if (first_contact < 0.)
            first_contact = integrator.time();
          last_contact = integrator.time();
        }
    }

  // @sect3{The check} against the analytic quasi-static Hertz impact of the
  // full cylinders.
  const ElasticCylinder cylinder{4.,
                                 material.youngs_modulus,
                                 material.poisson_ratio,
                                 material.density};
  const double          analytic =
    HertzImpactReference(cylinder, cylinder, 4., ApproachLaw::gerl_zippelius)
      .contact_duration();
  const double duration = last_contact - first_contact;
  const double error    = std::abs(duration / analytic - 1.);
  std::cout << "nurbs_impact: contact duration " << duration << " s, analytic "
            << analytic << " s (error " << 100. * error
            << " %, allowed 2 %); history in nurbs_impact_history.csv"
            << std::endl;
  return (first_contact >= 0. && error < 0.02) ? 0 : 1;
}
