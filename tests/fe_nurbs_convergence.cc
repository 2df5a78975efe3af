// Manufactured elasticity on the NURBS quarter annulus 1 <= r <= 2,
// 0 <= theta <= pi/2 with FE_NURBS (DiscretizationIGA in an ElasticBody,
// clamped on the whole boundary): u_x = u_y = phi = (r^2 - 1)(4 - r^2) x y
// vanishes on the whole boundary, so zero control points on the boundary
// are exact. The L2 errors at 4, 8 and 16 knot spans per direction are
// asserted against the measured values (p = 2: 2.892e-2, 3.405e-3, 4.181e-4
// m; p = 3: 2.327e-3, 1.449e-4, 9.284e-6 m) to 1 % relative, and the rate
// between 8 and 16 spans must be >= p + 1 - 0.1 (measured 3.03 and 3.96).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/sparse_direct.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/nurbs/geometries.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  const ElasticMaterial material; // E = 1000 Pa, nu = 0.2, plane strain

  double
  phi(const Point<2> &p)
  {
    const double r2 = p.square();
    return (r2 - 1.) * (4. - r2) * p[0] * p[1];
  }

  Tensor<1, 2>
  grad_phi(const Point<2> &p)
  {
    const double x = p[0], y = p[1], r2 = p.square();
    const double f = (r2 - 1.) * (4. - r2), df_dr2 = 5. - 2. * r2;
    Tensor<1, 2> g;
    g[0] = f * y + 2. * x * df_dr2 * x * y;
    g[1] = f * x + 2. * y * df_dr2 * x * y;
    return g;
  }

  SymmetricTensor<2, 2>
  exact_stress(const Point<2> &p)
  {
    // u = (phi, phi): grad u has both rows equal to grad phi.
    const Tensor<1, 2>    g = grad_phi(p);
    SymmetricTensor<2, 2> strain;
    strain[0][0] = g[0];
    strain[1][1] = g[1];
    strain[0][1] = 0.5 * (g[1] + g[0]);
    return material.stress(strain);
  }

  // b = -div sigma by central differences of the exact stress (error
  // O(h^2) = 1e-10, far below the discretisation errors measured).
  Tensor<1, 2>
  body_force(const Point<2> &p)
  {
    const double h = 1e-5;
    Tensor<1, 2> b;
    for (unsigned int j = 0; j < 2; ++j)
      {
        Point<2> plus = p, minus = p;
        plus[j] += h;
        minus[j] -= h;
        const auto ds = (exact_stress(plus) - exact_stress(minus)) / (2. * h);
        for (unsigned int i = 0; i < 2; ++i)
          b[i] -= ds[i][j];
      }
    return b;
  }

  double
  l2_error(const unsigned int degree, const unsigned int n_spans)
  {
    auto geometry = nurbs::quarter_annulus(1., 2.);
    geometry.patch.elevate_degree(0, degree - 2);
    geometry.patch.elevate_degree(1, degree - 2);
    geometry.patch.refine_uniformly(n_spans);
    // Zero displacement on the whole boundary (both components on the arcs
    // and the straight sides): ElasticBody builds the constraints and the
    // stiffness.
    std::vector<RollerCondition> clamped;
    for (const types::boundary_id id :
         {BodyGeometry::curved_boundary_id, BodyGeometry::symmetry_boundary_id})
      for (const unsigned int c : {0u, 1u})
        clamped.push_back({id, c});
    const ElasticBody<2>             body("annulus",
                              std::make_unique<DiscretizationIGA<2>>(geometry),
                              material,
                              MassScheme::hrz,
                              clamped,
                              Tensor<1, 2>());
    const Discretization<2>         &disc        = body.discretization();
    const AffineConstraints<double> &constraints = body.constraints();

    // Load vector through the same interface as every assembly.
    Vector<double> rhs;
    assemble_load_vector<2>(disc, body_force, constraints, rhs);

    SparseDirectUMFPACK solver;
    solver.initialize(body.stiffness_matrix());
    Vector<double> u(disc.n_dofs());
    solver.vmult(u, rhs);
    constraints.distribute(u);

    // L2 error with a richer rule.
    Vector<double> u_dofs(disc.dof_handler().n_dofs());
    disc.to_dof_handler_vector(u, u_dofs);
    const QGauss<2>             quadrature(degree + 4);
    FEValues<2>                 error_values(disc.mapping(),
                             disc.fe(),
                             quadrature,
                             update_values | update_quadrature_points |
                               update_JxW_values);
    std::vector<Vector<double>> values(quadrature.size(), Vector<double>(2));
    double                      error = 0.;
    for (const auto &cell : disc.dof_handler().active_cell_iterators())
      {
        error_values.reinit(cell);
        error_values.get_function_values(u_dofs, values);
        for (const unsigned int q : error_values.quadrature_point_indices())
          {
            const double exact = phi(error_values.quadrature_point(q));
            for (unsigned int c = 0; c < 2; ++c)
              error += (values[q](c) - exact) * (values[q](c) - exact) *
                       error_values.JxW(q);
          }
      }
    return std::sqrt(error);
  }
} // namespace

int
main()
{
  // Measured L2 errors (m) at 4, 8 and 16 spans per direction, asserted to
  // 1 % relative.
  const std::map<unsigned int, std::vector<double>> expected = {
    {2u, {2.892e-2, 3.405e-3, 4.181e-4}},
    {3u, {2.327e-3, 1.449e-4, 9.284e-6}}};
  for (const unsigned int degree : {2u, 3u})
    {
      std::vector<double> errors;
      for (const unsigned int n : {4u, 8u, 16u})
        {
          errors.push_back(l2_error(degree, n));
          isoimpact_tests::check_close("p = " + std::to_string(degree) + ", " +
                                         std::to_string(n) + " x " +
                                         std::to_string(n) +
                                         " spans: L2 error [m]",
                                       errors.back(),
                                       expected.at(degree)[errors.size() - 1],
                                       0.01);
        }
      const double rate = std::log2(errors[1] / errors[2]);
      isoimpact_tests::check_true("p = " + std::to_string(degree) +
                                    ": L2 rate " + std::to_string(rate) +
                                    " >= p + 1 - 0.1",
                                  rate >= degree + 1 - 0.1);
    }
  return isoimpact_tests::report();
}
