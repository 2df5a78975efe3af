// Patch test of the stiffness (FE_Q(2), MappingQ(2)) on a rectangle, a
// locally refined rectangle (hanging nodes) and the half disk (distorted,
// curved cells). The element is isoparametric and its functions sum to one,
// so a field linear in the physical coordinates, set node by node from
// dof_position and dof_component, is represented exactly:
//   u = A x + b  ->  eps = sym(A), sigma = lambda tr(eps) I + 2 mu eps
// everywhere. Checked:
// 1. strain energy 0.5 u^T K u = 0.5 V sigma(A) : sym(A), V the area of the
//    mesh (integrate_mass with density 1; for the half disk the discrete
//    area, not pi R^2 / 2). Tolerance 1e-10 relative: the quadrature of
//    the stiffness integrates the (rational on curved cells) integrand of
//    a constant strain exactly because the strain is constant, so only
//    round-off (1e-13 measured) remains.
// 2. The patch test proper: (K u)_i = 0 for every unknown not on the
//    boundary (the interior residual of a linear field vanishes), and K u = 0
//    for all unknowns for a linearised rigid motion u = W x + b, W skew;
//    both to 1e-10 relative to ||K||_inf ||u||_2 (||K||_inf bounds the
//    spectral norm of the symmetric K; round-off gives ~1e-16 sqrt(n)).
//    Control: the boundary residual of the non-rigid field is 1.9e-4 ..
//    3.7e-4 relative (asserted > 1e-6), so the check can fail.
// 3. strain and stress at points of each cell (Gauss points and a grid that
//    includes the vertices), evaluated with FEValues on the DoFHandler via
//    to_dof_handler_vector, equal sym(A) and sigma(A) to 1e-10 relative to
//    their norm. On the rectangles round-off gives 3e-14. On the half disk
//    the measured error is 5e-11 (strain) and 6.5e-11 (stress): deal.II's
//    TransfiniteInterpolationManifold gives the mapping support points of
//    a line seen from the two neighbouring cells up to 3.5e-11 apart (a
//    pull-back tolerance; dof_position keeps one of them), so the linear
//    field is linear only to ~3e-11 / h in its gradient. This grows under
//    refinement (2.6e-10 with 3 levels), hence 2 levels here.
// The elastic constants are recomputed here from E and nu (plane strain and
// plane stress), independently of ElasticMaterial.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <cmath>
#include <memory>
#include <set>
#include <string>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  // sigma(eps) from E, nu, without ElasticMaterial.
  SymmetricTensor<2, 2>
  reference_stress(const SymmetricTensor<2, 2> &eps,
                   const double                 E,
                   const double                 nu,
                   const bool                   plane_strain)
  {
    SymmetricTensor<2, 2> sigma;
    if (plane_strain)
      {
        const double c = E / ((1. + nu) * (1. - 2. * nu));
        sigma[0][0]    = c * ((1. - nu) * eps[0][0] + nu * eps[1][1]);
        sigma[1][1]    = c * (nu * eps[0][0] + (1. - nu) * eps[1][1]);
      }
    else
      {
        const double c = E / (1. - nu * nu);
        sigma[0][0]    = c * (eps[0][0] + nu * eps[1][1]);
        sigma[1][1]    = c * (nu * eps[0][0] + eps[1][1]);
      }
    sigma[0][1] = E / (1. + nu) * eps[0][1];
    return sigma;
  }

  Vector<double>
  linear_field(const Discretization<2> &discretization,
               const Tensor<2, 2>      &A,
               const Tensor<1, 2>      &b)
  {
    Vector<double> u(discretization.n_dofs());
    for (types::global_dof_index i = 0; i < u.size(); ++i)
      {
        const Tensor<1, 2> value = A * discretization.dof_position(i) + b;
        u(i)                     = value[discretization.dof_component(i)];
      }
    return u;
  }

  void
  run(const std::string  &name,
      const BodyGeometry &geometry,
      const bool          plane_strain)
  {
    std::cout << "--- " << name
              << (plane_strain ? ", plane strain" : ", plane stress")
              << std::endl;
    ElasticMaterial material;
    material.youngs_modulus = 1000.;
    material.poisson_ratio  = 0.2;
    material.plane_strain   = plane_strain;
    const ElasticBody<2>        body("patch",
                              std::make_unique<DiscretizationFEA<2>>(geometry,
                                                                     2),
                              material,
                              MassScheme::row_sum,
                              {},
                              Tensor<1, 2>());
    const Discretization<2>    &discretization = body.discretization();
    const SparseMatrix<double> &K              = body.stiffness_matrix();
    const double                area = integrate_mass(discretization, 1.);
    std::cout << "    " << discretization.triangulation().n_active_cells()
              << " cells, " << discretization.n_dofs() << " unknowns, "
              << body.constraints().n_constraints() << " constrained, area "
              << area << std::endl;

    Tensor<2, 2> A;
    A[0][0] = 0.3;
    A[0][1] = 0.2;
    A[1][0] = -0.1;
    A[1][1] = -0.15;
    const Tensor<1, 2>          b({0.7, -0.4});
    const SymmetricTensor<2, 2> eps = symmetrize(A);
    const SymmetricTensor<2, 2> sigma =
      reference_stress(eps,
                       material.youngs_modulus,
                       material.poisson_ratio,
                       plane_strain);

    // 1. Strain energy.
    const Vector<double> u = linear_field(discretization, A, b);
    CHECK_CLOSE(body.strain_energy(u), 0.5 * area * (sigma * eps), 1e-10);

    // 2. Residuals. Unknowns on the boundary: the nodes of all boundary
    // segments (ids 0..3 cover the rectangle's sides and the half disk's arc
    // and cut).
    std::set<types::global_dof_index> boundary;
    for (types::boundary_id id = 0; id < 4; ++id)
      for (const auto &segment : discretization.boundary_segments(id))
        for (const auto &node : segment.node_dofs)
          for (const auto dof : node)
            boundary.insert(dof);
    CHECK_TRUE(!boundary.empty() && boundary.size() < discretization.n_dofs());

    Vector<double> Ku(u.size());
    K.vmult(Ku, u);
    const double scale    = K.linfty_norm() * u.l2_norm();
    double       interior = 0., on_boundary = 0.;
    for (types::global_dof_index i = 0; i < u.size(); ++i)
      if (!body.constraints().is_constrained(i))
        (boundary.count(i) ? on_boundary : interior) =
          std::max(boundary.count(i) ? on_boundary : interior, std::abs(Ku(i)));
    CHECK_CLOSE_ABS(interior / scale, 0., 1e-10);
    // Control: a linear field does load the boundary.
    CHECK_TRUE(on_boundary / scale > 1e-6);

    Tensor<2, 2> W;
    W[0][1]                    = -0.25;
    W[1][0]                    = 0.25;
    const Vector<double> rigid = linear_field(discretization, W, b);
    K.vmult(Ku, rigid);
    body.constraints().set_zero(Ku);
    CHECK_CLOSE_ABS(Ku.l2_norm() / (K.linfty_norm() * rigid.l2_norm()),
                    0.,
                    1e-10);
    CHECK_CLOSE_ABS(body.strain_energy(rigid) /
                      (0.5 * K.linfty_norm() * rigid.norm_sqr()),
                    0.,
                    1e-10);

    // 3. Strain and stress in the cells, via the DoFHandler.
    Vector<double> nodal(discretization.dof_handler().n_dofs());
    Vector<double> u_distributed = u;
    body.constraints().distribute(u_distributed);
    discretization.to_dof_handler_vector(u_distributed, nodal);
    const FEValuesExtractors::Vector displacement(0);
    for (const auto &quadrature :
         {Quadrature<2>(QGauss<2>(3)),
          Quadrature<2>(QIterated<2>(QTrapezoid<1>(), 3))})
      {
        FEValues<2>                        fe_values(discretization.mapping(),
                              discretization.fe(),
                              quadrature,
                              update_gradients | update_values |
                                update_quadrature_points);
        std::vector<SymmetricTensor<2, 2>> strains(quadrature.size());
        std::vector<Tensor<1, 2>>          values(quadrature.size());
        double strain_error = 0., stress_error = 0., value_error = 0.;
        for (const auto &cell :
             discretization.dof_handler().active_cell_iterators())
          {
            fe_values.reinit(cell);
            fe_values[displacement].get_function_symmetric_gradients(nodal,
                                                                     strains);
            fe_values[displacement].get_function_values(nodal, values);
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              {
                strain_error =
                  std::max(strain_error, (strains[q] - eps).norm());
                stress_error =
                  std::max(stress_error,
                           (material.stress(strains[q]) - sigma).norm());
                value_error = std::max(
                  value_error,
                  (values[q] - (A * fe_values.quadrature_point(q) + b)).norm());
              }
          }
        CHECK_CLOSE_ABS(strain_error / eps.norm(), 0., 1e-10);
        CHECK_CLOSE_ABS(stress_error / sigma.norm(), 0., 1e-10);
        // The field itself is A x + b at the mapped points (isoparametric).
        CHECK_CLOSE_ABS(value_error, 0., 1e-10);
      }
  }
} // namespace

int
main()
{
  BodyGeometry rectangle;
  rectangle.shape              = BodyGeometry::Shape::rectangle;
  rectangle.lower_left         = Point<2>(-1., 0.5);
  rectangle.upper_right        = Point<2>(2., 2.);
  rectangle.global_refinements = 2;

  BodyGeometry rectangle_hanging      = rectangle;
  rectangle_hanging.local_refinements = 2;
  rectangle_hanging.refinement_center = Point<2>(-1., 0.5);
  rectangle_hanging.refinement_radius = 0.5;

  BodyGeometry half_disk; // R = 4, centre (0, 4)
  half_disk.global_refinements = 2;

  for (const bool plane_strain : {true, false})
    {
      run("rectangle", rectangle, plane_strain);
      run("rectangle with hanging nodes", rectangle_hanging, plane_strain);
      run("half disk", half_disk, plane_strain);
    }
  return isoimpact_tests::report();
}
