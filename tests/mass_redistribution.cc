// Mass redistribution (Contact/Mass redistribution, doc/formulation.md) on
// half disks (R = 4, level 2, roller on the symmetry cut as in the program)
// for FEA Q9 (HRZ, row-sum), FEA Q8 (HRZ) and IGA p2 (HRZ, row-sum):
// 1. the unconstrained unknowns of the arc (the contact surface) are
//    exactly the massless ones, and their masses are 0 (exactly);
// 2. per displacement component, the total mass sum m_i and the first
//    moment sum m_i X_i are kept to 1e-12 (relative to M and M R);
// 3. no other unknown loses mass (the exponential tilt gives every receiver
//    a positive share), and the acceleration of compute_acceleration() is 0
//    on the massless rows;
// 4. the stable-step bounds (Gershgorin over the massive rows; element by
//    element with the elements' shares scaled to the new masses and the
//    massless unknowns left out) and the power estimate of the interior are
//    finite and positive, and neither bound falls (no mass shrinks; the
//    contact springs, on massless rows, drop out of both);
// 5. a consistent mass is refused with an error.
#include <isoimpact/discretization/discretization.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/mechanics/stable_time_step.h>

#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "tests.h"

using namespace dealii;
using namespace isoimpact;

namespace
{
  std::unique_ptr<ElasticBody<2>>
  make_body(const DiscretizationMethod method,
            const FEAElement           element,
            const MassScheme           scheme)
  {
    BodyGeometry geometry;
    geometry.center             = Point<2>(0., 4.);
    geometry.radius             = 4.;
    geometry.global_refinements = 2;
    return std::make_unique<ElasticBody<2>>(
      "body",
      create_discretization<2>(method, geometry, 2, element),
      ElasticMaterial(),
      scheme,
      std::vector<RollerCondition>{{BodyGeometry::symmetry_boundary_id, 0}},
      Tensor<1, 2>());
  }

  void
  check(const std::string         &name,
        const DiscretizationMethod method,
        const FEAElement           element,
        const MassScheme           scheme)
  {
    std::cout << "--- " << name << ", " << to_string(scheme) << std::endl;
    auto        body    = make_body(method, element, scheme);
    const auto &d       = body->discretization();
    const auto  surface = d.boundary_segments(BodyGeometry::curved_boundary_id);
    const Vector<double> before = body->lumped_masses();
    const StableTimeStep plain  = compute_stable_time_step(*body, {});
    body->redistribute_mass(surface);
    const Vector<double> after = body->lumped_masses();

    std::set<types::global_dof_index> expected;
    for (const auto &segment : surface)
      for (const auto &node : segment.node_dofs)
        for (const auto dof : node)
          if (!body->constraints().is_constrained(dof))
            expected.insert(dof);
    const auto &massless = body->massless_dofs();
    CHECK_TRUE(std::set<types::global_dof_index>(massless.begin(),
                                                 massless.end()) == expected);
    double largest_massless = 0., smallest_other = 1e300;
    bool   none_lost = true;
    for (types::global_dof_index i = 0; i < after.size(); ++i)
      if (expected.count(i))
        largest_massless = std::max(largest_massless, std::abs(after(i)));
      else
        {
          none_lost &= after(i) >= before(i);
          if (!body->constraints().is_constrained(i))
            smallest_other = std::min(smallest_other, after(i));
        }
    CHECK_CLOSE_ABS(largest_massless, 0., 0.);
    CHECK_TRUE(smallest_other > 0.);
    CHECK_TRUE(none_lost);

    const double radius = 4.;
    for (unsigned int c = 0; c < 2; ++c)
      {
        double       mass_before = 0., mass_after = 0.;
        Tensor<1, 2> moment_before, moment_after;
        for (types::global_dof_index i = 0; i < after.size(); ++i)
          if (d.dof_component(i) == c)
            {
              mass_before += before(i);
              mass_after += after(i);
              moment_before += before(i) * d.dof_position(i);
              moment_after += after(i) * d.dof_position(i);
            }
        std::cout << "  component " << c << ": mass " << mass_before << " -> "
                  << mass_after << ", centre ("
                  << moment_before[0] / mass_before << ", "
                  << moment_before[1] / mass_before << ") -> ("
                  << moment_after[0] / mass_after << ", "
                  << moment_after[1] / mass_after << ")" << std::endl;
        isoimpact_tests::check_close("total mass, component " +
                                       std::to_string(c),
                                     mass_after,
                                     mass_before,
                                     1e-12);
        for (unsigned int a = 0; a < 2; ++a)
          isoimpact_tests::check_close("first moment " + std::to_string(a) +
                                         ", component " + std::to_string(c),
                                       moment_after[a],
                                       moment_before[a],
                                       1.,
                                       1e-12 * mass_before * radius,
                                       true);
      }

    // Zero acceleration on the massless rows for a force on every row.
    Vector<double> u(body->n_dofs()), f(body->n_dofs()), a(body->n_dofs());
    for (types::global_dof_index i = 0; i < u.size(); ++i)
      {
        u(i) = 1e-3 * std::sin(1. + i);
        f(i) = std::cos(2. + i);
      }
    body->constraints().set_zero(u);
    body->compute_acceleration(u, f, a);
    double largest = 0.;
    for (const auto i : massless)
      largest = std::max(largest, std::abs(a(i)));
    CHECK_CLOSE_ABS(largest, 0., 0.);

    const StableTimeStep step = compute_stable_time_step(*body, {});
    std::cout << "  stable step: Gershgorin bound " << plain.gershgorin_bound
              << " -> " << step.gershgorin_bound << " s, element bound "
              << plain.element_bound << " -> " << step.element_bound
              << " s, estimate " << plain.power_estimate << " -> "
              << step.power_estimate << " s" << std::endl;
    CHECK_TRUE(step.gershgorin_bound > 0. &&
               std::isfinite(step.gershgorin_bound));
    CHECK_TRUE(step.element_bound >= plain.element_bound);
    CHECK_TRUE(step.power_estimate > 0. && std::isfinite(step.power_estimate));
    // The interior's step bounds the true one; the Gershgorin bound stays
    // below the estimate.
    CHECK_TRUE(step.bound() <= step.power_estimate);
    CHECK_TRUE(step.gershgorin_bound >= plain.gershgorin_bound);
  }
} // namespace

int
main()
{
  check("FEA Q9",
        DiscretizationMethod::fea,
        FEAElement::lagrange,
        MassScheme::hrz);
  check("FEA Q9",
        DiscretizationMethod::fea,
        FEAElement::lagrange,
        MassScheme::row_sum);
  check("FEA Q8",
        DiscretizationMethod::fea,
        FEAElement::serendipity,
        MassScheme::hrz);
  check("IGA p2",
        DiscretizationMethod::iga,
        FEAElement::lagrange,
        MassScheme::hrz);
  check("IGA p2",
        DiscretizationMethod::iga,
        FEAElement::lagrange,
        MassScheme::row_sum);

  std::cout << "--- consistent mass is refused" << std::endl;
  auto consistent = make_body(DiscretizationMethod::fea,
                              FEAElement::lagrange,
                              MassScheme::consistent);
  bool refused    = false;
  try
    {
      consistent->redistribute_mass(
        consistent->discretization().boundary_segments(
          BodyGeometry::curved_boundary_id));
    }
  catch (const std::exception &e)
    {
      refused = std::string(e.what()).find("consistent mass is not "
                                           "supported") != std::string::npos;
    }
  CHECK_TRUE(refused);
  return isoimpact_tests::report();
}
