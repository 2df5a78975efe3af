// Rigid obstacles (RigidObstacle, RigidObstacleContact), static checks with
// exact values.
//
// A. Gap and normal of single points: plane through (0, 0) with the normal
//    (0, 2) (normalised to (0, 1)): g(1, -0.3) = -0.3, n = (0, 1); a tilted
//    plane through (1, 1) with normal (1, 1): g(0, 0) = -sqrt(2);
//    cylinder centre (0, -4), radius 4: g(0, -0.1) = -0.1, n = (0, 1);
//    g(3, 0) = 5 - 4 = 1, n = (0.6, 0.8). 1e-14.
// B. One straight quadratic segment (nodes (0, 0.05), (0.5, 0.05),
//    (1, 0.05), Lagrange, length L = 1) displaced by u_y = -0.06, i.e. at
//    y = -0.01 (g0 = 0.01 below the plane y = 0): every Gauss point has
//    g = -g0, so with 4 Gauss points (exact for the quadratic functions)
//    - resultant (0, eps g0 L), nodal forces eps g0 L (1/6, 2/3, 1/6) in y,
//      none in x;
//    - energy 1/2 eps g0^2 L, max pressure eps g0, 4 active points; 1e-12;
//    - the consistent pressure (a flat punch, uniform overlap): eps g0 at
//      every Gauss point, 1e-12.
//    Without the displacement (segment above the plane): no force.
// C. A radial segment against the cylinder of A: nodes (0, -0.03),
//    (0, -0.02), (0, -0.01) (inside the circle, normal (0, 1), g = y):
//    resultant eps int |y| dy = eps 4e-4 in y, energy 1/2 eps int y^2 dy =
//    eps (0.03^3 - 0.01^3)/6; both integrands are polynomials of degree
//    <= 2, exact with 4 Gauss points: 1e-12. The maximal Gauss-point
//    pressure is that of the deepest Gauss point, eps |y(eta_1)|.
// D. A horizontal segment y = -0.01, x in [-1, 1], against the same
//    cylinder (gap varies along the segment, normal turns): the forces are
//    minus the gradient of the contact energy, checked by central
//    differences of the energy in every unknown (h = 1e-6): 1e-6 relative to
//    the largest nodal force.
#include <isoimpact/mechanics/rigid_obstacle.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  const double eps = 2e5;

  // A quadratic Lagrange segment through three points (eta = 0, 1/2, 1).
  BoundarySegment<2>
  quadratic_segment(const Point<2> &a, const Point<2> &b, const Point<2> &c)
  {
    BoundarySegment<2> segment;
    segment.degree         = 2;
    segment.node_positions = {a, b, c};
    segment.node_weights   = {1., 1., 1.};
    segment.node_dofs      = {{{0, 1}}, {{2, 3}}, {{4, 5}}};
    FullMatrix<double> values(3, 3);
    for (unsigned int k = 0; k < 3; ++k)
      values(k, k) = 1.;
    segment.bernstein_coefficients = bernstein_coefficients_from_values(values);
    return segment;
  }

  ObstacleContactSettings
  settings()
  {
    ObstacleContactSettings s;
    s.penalty             = eps;
    s.n_quadrature_points = 4;
    return s;
  }

  Tensor<1, 2>
  vec(const double x, const double y)
  {
    Tensor<1, 2> t;
    t[0] = x;
    t[1] = y;
    return t;
  }
} // namespace

int
main()
{
  using isoimpact_tests::check_close;
  const auto plane    = RigidObstacle<2>::plane(Point<2>(0., 0.), vec(0., 2.));
  const auto cylinder = RigidObstacle<2>::cylinder(Point<2>(0., -4.), 4.);

  std::cout << "A. gap and normal of single points" << std::endl;
  {
    // The gap at x to 1e-14 relative and, if given, the normal to 1e-14.
    const auto check_gap = [](const std::string      &name,
                              const RigidObstacle<2> &obstacle,
                              const Point<2>         &x,
                              const double            expected_gap,
                              const Tensor<1, 2>     *expected_normal) {
      Tensor<1, 2>       n;
      std::ostringstream at;
      at << name << " at (" << x << ")";
      check_close(at.str() + ": gap", obstacle.gap(x, n), expected_gap, 1e-14);
      if (expected_normal)
        check_close(at.str() + ": |n - n_expected|",
                    (n - *expected_normal).norm(),
                    0.,
                    1.,
                    1e-14,
                    true);
    };
    const Tensor<1, 2> up = vec(0., 1.), diagonal = vec(0.6, 0.8);
    const auto tilted = RigidObstacle<2>::plane(Point<2>(1., 1.), vec(1., 1.));
    check_gap("plane", plane, Point<2>(1., -0.3), -0.3, &up);
    check_gap("tilted plane",
              tilted,
              Point<2>(0., 0.),
              -std::sqrt(2.),
              nullptr);
    check_gap("cylinder", cylinder, Point<2>(0., -0.1), -0.1, &up);
    check_gap("cylinder", cylinder, Point<2>(3., 0.), 1., &diagonal);
  }

  std::cout << "B. a flat segment pressed g0 = 0.01 into the plane"
            << std::endl;
  {
    const double                  g0 = 0.01, L = 1.;
    const RigidObstacleContact<2> contact(
      settings(),
      plane,
      {quadratic_segment(Point<2>(0., 0.05),
                         Point<2>(0.5, 0.05),
                         Point<2>(1., 0.05))});
    Vector<double> u(6), f(6);
    for (unsigned int k = 0; k < 3; ++k)
      u(2 * k + 1) = -0.06;
    const ContactResult<2> result = contact.evaluate({&u}, {}, {&f}, true);
    check_close("resultant y", result.force_on_body_0[1], eps * g0 * L, 1e-12);
    check_close("resultant x",
                result.force_on_body_0[0],
                0.,
                1.,
                1e-12 * eps * g0 * L,
                true);
    const double nodal[3] = {1. / 6., 2. / 3., 1. / 6.};
    for (unsigned int k = 0; k < 3; ++k)
      {
        check_close("nodal force y, node " + std::to_string(k),
                    f(2 * k + 1),
                    eps * g0 * L * nodal[k],
                    1e-12);
        check_close("nodal force x, node " + std::to_string(k),
                    f(2 * k),
                    0.,
                    1.,
                    1e-12 * eps * g0 * L,
                    true);
      }
    check_close("energy", result.energy, 0.5 * eps * g0 * g0 * L, 1e-12);
    // A uniform overlap (flat punch): the Gauss-point pressure and the
    // consistent pressure field are both eps g0 exactly.
    check_close("max Gauss-point pressure",
                result.max_gauss_point_pressure,
                eps * g0,
                1e-12);
    check_close("max consistent pressure",
                result.max_pressure,
                eps * g0,
                1e-12);
    CHECK_TRUE(result.n_active_points == 4 && result.points.size() == 4);
    for (const auto &point : result.points)
      CHECK_TRUE(std::abs(point.gap + g0) < 1e-14 &&
                 std::abs(point.gauss_point_pressure - eps * g0) < 1e-9 &&
                 std::abs(point.pressure - eps * g0) < 1e-9);

    Vector<double>         zero(6), f0(6);
    const ContactResult<2> free = contact.evaluate({&zero}, {}, {&f0}, false);
    CHECK_TRUE(free.n_active_points == 0 && f0.l2_norm() == 0. &&
               free.energy == 0.);
  }

  std::cout << "C. a radial segment inside the cylinder" << std::endl;
  {
    const RigidObstacleContact<2> contact(
      settings(),
      cylinder,
      {quadratic_segment(Point<2>(0., -0.03),
                         Point<2>(0., -0.02),
                         Point<2>(0., -0.01))});
    Vector<double>         u(6), f(6);
    const ContactResult<2> result = contact.evaluate({&u}, {}, {&f}, false);
    check_close("resultant y", result.force_on_body_0[1], eps * 4e-4, 1e-12);
    check_close("energy",
                result.energy,
                eps * (std::pow(0.03, 3) - std::pow(0.01, 3)) / 6.,
                1e-12);
    // The deepest Gauss point: eta_1 = (1 - sqrt(3/7 + 2/7 sqrt(6/5)))/2.
    const double eta_1 =
      0.5 * (1. - std::sqrt(3. / 7. + 2. / 7. * std::sqrt(6. / 5.)));
    check_close("max pressure (deepest Gauss point)",
                result.max_gauss_point_pressure,
                eps * (0.03 - 0.02 * eta_1),
                1e-12);
  }

  std::cout << "D. forces = -grad energy, horizontal segment vs cylinder"
            << std::endl;
  {
    const RigidObstacleContact<2> contact(
      settings(),
      cylinder,
      {quadratic_segment(Point<2>(-1., -0.01),
                         Point<2>(0.1, -0.01),
                         Point<2>(1., -0.01))});
    Vector<double>         u(6), f(6);
    const ContactResult<2> result = contact.evaluate({&u}, {}, {&f}, false);
    CHECK_TRUE(result.n_active_points > 0);
    const double h         = 1e-6;
    double       max_error = 0.;
    for (unsigned int i = 0; i < 6; ++i)
      {
        Vector<double> up(u), um(u), scratch(6);
        up(i) += h;
        um(i) -= h;
        const double dE =
          (contact.evaluate({&up}, {}, {&scratch}, false).energy -
           contact.evaluate({&um}, {}, {&scratch}, false).energy) /
          (2. * h);
        max_error = std::max(max_error, std::abs(f(i) + dE));
      }
    check_close("max |f + dE/du| / max |f|",
                max_error / f.linfty_norm(),
                0.,
                1.,
                1e-6,
                true);
  }

  return isoimpact_tests::report();
}
