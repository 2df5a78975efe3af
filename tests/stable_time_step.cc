// The stable time step of central differences (mechanics/stable_time_step.h)
// against exact values, and its two guaranteed bounds against the sharp
// estimate.
// 1. A square of 16 x 16 square Q2 elements of edge h, lumped mass, nu = 0.3,
//    c_p the dilatational wave speed: omega_max h / c_p = 5.44 free and 5.02
//    clamped (../shared/notes, issue 9), so dt_crit = 2 h / (5.44 c_p) resp.
//    2 h / (5.02 c_p). The power estimate must give these values to 1 %
//    (it converges from above in dt, 2000 iterations); both bounds must lie
//    at or below it and within 25 % of it.
// 2. Penalty springs lower the step: a half disk (the benchmark's, 256 Q2
//    cells, HRZ) with the springs of a rigid plane of penalty 2e5 Pa/m on its
//    arc: estimate with springs < estimate without; bounds below the
//    estimate with springs and within 25 % of it.
#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/stable_time_step.h>

#include <cmath>
#include <memory>

#include "tests.h"

using namespace dealii;
using namespace isoimpact;
using namespace isoimpact_tests;

namespace
{
  ElasticMaterial
  material()
  {
    ElasticMaterial m;
    m.youngs_modulus = 1000.;
    m.poisson_ratio  = 0.3;
    m.density        = 1.;
    return m;
  }

  void
  check_bounds(const std::string &what, const StableTimeStep &step)
  {
    std::cout << what << ": element bound " << step.element_bound
              << " s, Gershgorin bound " << step.gershgorin_bound
              << " s, power estimate " << step.power_estimate << " s"
              << std::endl;
    check_true(what + ": element bound <= estimate",
               step.element_bound <= step.power_estimate);
    check_true(what + ": Gershgorin bound <= estimate",
               step.gershgorin_bound <= step.power_estimate);
    check_close(what + ": bound within 25 % of the estimate",
                step.bound(),
                step.power_estimate,
                0.25);
  }

  void
  square(const bool clamped, const MassScheme scheme, const double omega_h)
  {
    BodyGeometry geometry;
    geometry.shape              = BodyGeometry::Shape::rectangle;
    geometry.lower_left         = Point<2>(0., 0.);
    geometry.upper_right        = Point<2>(1., 1.);
    geometry.global_refinements = 4;
    std::vector<RollerCondition> clamps;
    if (clamped)
      for (types::boundary_id b = 0; b < 4; ++b)
        for (unsigned int c = 0; c < 2; ++c)
          clamps.push_back({b, c});
    const ElasticBody<2> body(
      "square",
      create_discretization<2>(DiscretizationMethod::fea, geometry, 2),
      material(),
      scheme,
      clamps,
      Tensor<1, 2>());
    const StableTimeStep step = compute_stable_time_step<2>(body, {}, 2000);
    const double         h    = 1. / 16.;
    const std::string    what = std::string(clamped ? "clamped" : "free") +
                             " square, " + to_string(scheme);
    check_close(what + ": omega_max h / c_p",
                2. / step.power_estimate * h /
                  material().dilatational_wave_speed(),
                omega_h,
                0.01);
    check_bounds(what, step);
  }

  void
  half_disk_on_springs()
  {
    BodyGeometry geometry;
    geometry.global_refinements = 3;
    const ElasticBody<2> body(
      "half disk",
      create_discretization<2>(DiscretizationMethod::fea, geometry, 2),
      material(),
      MassScheme::hrz,
      {{BodyGeometry::symmetry_boundary_id, 0}},
      Tensor<1, 2>());
    const auto segments =
      body.discretization().boundary_segments(BodyGeometry::curved_boundary_id);
    const StableTimeStep free = compute_stable_time_step<2>(body, {});
    const StableTimeStep with_springs =
      compute_stable_time_step<2>(body, {{&segments, 2e5}});
    std::cout << "half disk: estimate without springs " << free.power_estimate
              << " s, with " << with_springs.power_estimate << " s"
              << std::endl;
    check_true("springs lower the estimate",
               with_springs.power_estimate < 0.99 * free.power_estimate);
    check_bounds("half disk on springs", with_springs);
  }
} // namespace

int
main()
{
  square(false, MassScheme::hrz, 5.44);
  square(true, MassScheme::hrz, 5.02);
  half_disk_on_springs();
  return report();
}
