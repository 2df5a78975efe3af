// Set-ups shared by the tests: the benchmark's half disk, a displacement
// field linear in the physical coordinates, and the patch test of the
// stiffness, for any discretisation (FEA or IGA).
#ifndef isoimpact_test_helpers_h
#define isoimpact_test_helpers_h

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>
#include <isoimpact/nurbs/geometries.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "tests.h"

namespace isoimpact_tests
{
  // The half disk of the benchmark: radius 4 m, centre (0, 4), touching the
  // origin, where local refinement (within 1.5 m) concentrates.
  inline constexpr double       half_disk_radius = 4.;
  inline const dealii::Point<2> half_disk_center(0., 4.);

  inline isoimpact::BodyGeometry
  half_disk(const unsigned int global_refinements,
            const unsigned int local_refinements = 0)
  {
    isoimpact::BodyGeometry body;
    body.shape              = isoimpact::BodyGeometry::Shape::half_disk;
    body.center             = half_disk_center;
    body.radius             = half_disk_radius;
    body.global_refinements = global_refinements;
    body.local_refinements  = local_refinements;
    body.refinement_center  = dealii::Point<2>(0., 0.);
    body.refinement_radius  = 1.5;
    return body;
  }

  // The half disk as one NURBS patch of the given degree with knots graded
  // toward the contact corner (multi-patch bodies refuse graded refinement).
  inline std::unique_ptr<isoimpact::Discretization<2>>
  graded_half_disk_iga(const unsigned int global_refinements,
                       const unsigned int layers,
                       const unsigned int degree)
  {
    auto geometry =
      isoimpact::nurbs::half_disk(half_disk_radius, half_disk_center);
    for (unsigned int d = 0; d < 2; ++d)
      geometry.patch.elevate_degree(d, degree - 2);
    geometry.patch.refine_uniformly(1u << global_refinements);
    for (unsigned int d = 0; d < 2; ++d)
      geometry.patch.refine_graded(d, 0, layers, 2.);
    return std::make_unique<isoimpact::DiscretizationIGA<2>>(geometry);
  }

  // u = A x + b, set unknown by unknown from dof_position and dof_component
  // (exact for bases that sum to one and reproduce x).
  inline dealii::Vector<double>
  linear_field(const isoimpact::Discretization<2> &discretization,
               const dealii::Tensor<2, 2>         &A,
               const dealii::Tensor<1, 2>         &b)
  {
    dealii::Vector<double> u(discretization.n_dofs());
    for (dealii::types::global_dof_index i = 0; i < u.size(); ++i)
      u(i) = (A * discretization.dof_position(i) +
              b)[discretization.dof_component(i)];
    return u;
  }

  // sigma(eps) from E and nu, independently of ElasticMaterial.
  inline dealii::SymmetricTensor<2, 2>
  reference_stress(const dealii::SymmetricTensor<2, 2> &eps,
                   const double                         E,
                   const double                         nu,
                   const bool                           plane_strain)
  {
    dealii::SymmetricTensor<2, 2> sigma;
    const double                  c =
      plane_strain ? E / ((1. + nu) * (1. - 2. * nu)) : E / (1. - nu * nu);
    const double c0 = plane_strain ? 1. - nu : 1.;
    sigma[0][0]     = c * (c0 * eps[0][0] + nu * eps[1][1]);
    sigma[1][1]     = c * (nu * eps[0][0] + c0 * eps[1][1]);
    sigma[0][1]     = E / (1. + nu) * eps[0][1];
    return sigma;
  }

  // Options of the patch test: relative tolerances of the strain energies
  // and of the residuals, strains, stresses and values; whether to check at
  // the cell vertices too (not where det J = 0 at a vertex, as at two
  // corners of the one-patch half disk, nurbs::half_disk).
  struct PatchTestOptions
  {
    double energy_tolerance = 1e-10;
    double field_tolerance  = 1e-10;
    bool   at_vertices      = true;
  };

  /**
   * The patch test of the stiffness (E = 1000 Pa, nu = 0.2) for a field
   * u = A x + b linear in the physical coordinates, which every basis here
   * represents exactly (functions summing to one, isoparametric or exact
   * geometry), so eps = sym(A) and sigma = sigma(A) everywhere. Checked:
   * 1. strain energy 0.5 u^T K u = 0.5 V sigma : eps, V the area of the mesh
   *    (integrate_mass with density 1);
   * 2. (K u)_i = 0 for every unconstrained unknown off the boundary, and
   *    K u = 0 (constrained entries set to zero) and 0.5 u^T K u = 0 for a
   *    linearised rigid motion u = W x + b, W skew; relative to
   *    ||K||_inf ||u||_2 (||K||_inf bounds the spectral norm of the
   *    symmetric K). Control: the boundary residual of the non-rigid field is
   *    above 1e-6 relative, so the check can fail;
   * 3. strain, stress (of ElasticMaterial) and value at the points of
   *    QGauss(3), QGauss(4) and (options.at_vertices) a 4 x 4 grid that
   *    includes the vertices of each cell, evaluated with FEValues on the
   *    DoFHandler vector (to_dof_handler_vector), equal sym(A), sigma(A)
   *    and A x + b, relative to |eps| and |sigma| (values absolute).
   */
  inline void
  check_patch_test(const std::string                            &name,
                   std::unique_ptr<isoimpact::Discretization<2>> discretization,
                   const bool                                    plane_strain,
                   const PatchTestOptions                       &options = {})
  {
    isoimpact::ElasticMaterial material;
    material.youngs_modulus = 1000.;
    material.poisson_ratio  = 0.2;
    material.plane_strain   = plane_strain;
    const isoimpact::ElasticBody<2>     body("patch",
                                         std::move(discretization),
                                         material,
                                         isoimpact::MassScheme::hrz,
                                         {},
                                         dealii::Tensor<1, 2>());
    const isoimpact::Discretization<2> &disc = body.discretization();
    const dealii::SparseMatrix<double> &K    = body.stiffness_matrix();
    const double area = isoimpact::integrate_mass(disc, 1.);
    std::cout << "--- patch test, " << name << ", " << disc.name()
              << (plane_strain ? ", plane strain: " : ", plane stress: ")
              << disc.triangulation().n_active_cells() << " cells, "
              << disc.n_dofs() << " unknowns, "
              << body.constraints().n_constraints() << " constrained, area "
              << area << std::endl;

    dealii::Tensor<2, 2> A;
    A[0][0] = 0.3;
    A[0][1] = 0.2;
    A[1][0] = -0.1;
    A[1][1] = -0.15;
    const dealii::Tensor<1, 2>          b({0.7, -0.4});
    const dealii::SymmetricTensor<2, 2> eps = dealii::symmetrize(A);
    const dealii::SymmetricTensor<2, 2> sigma =
      reference_stress(eps,
                       material.youngs_modulus,
                       material.poisson_ratio,
                       plane_strain);

    // 1. Strain energy.
    const dealii::Vector<double> u = linear_field(disc, A, b);
    check_close("0.5 u^T K u",
                body.strain_energy(u),
                0.5 * area * (sigma * eps),
                options.energy_tolerance);

    // 2. Residuals. Unknowns on the boundary: the nodes of all boundary
    // segments (ids 0..3 cover the rectangle's sides and the half disk's arc
    // and cut).
    std::set<dealii::types::global_dof_index> boundary;
    for (dealii::types::boundary_id id = 0; id < 4; ++id)
      for (const auto &segment : disc.boundary_segments(id))
        for (const auto &node : segment.node_dofs)
          boundary.insert(node.begin(), node.end());
    CHECK_TRUE(!boundary.empty() && boundary.size() < disc.n_dofs());

    dealii::Vector<double> Ku(u.size());
    K.vmult(Ku, u);
    const double scale    = K.linfty_norm() * u.l2_norm();
    double       interior = 0., on_boundary = 0.;
    for (dealii::types::global_dof_index i = 0; i < u.size(); ++i)
      if (!body.constraints().is_constrained(i))
        {
          double &largest = boundary.count(i) ? on_boundary : interior;
          largest         = std::max(largest, std::abs(Ku(i)));
        }
    check_close("interior |K u| / (|K| |u|)",
                interior / scale,
                0.,
                1.,
                options.field_tolerance,
                true);
    // Control: a linear field does load the boundary.
    CHECK_TRUE(on_boundary / scale > 1e-6);

    dealii::Tensor<2, 2> W;
    W[0][1]                            = -0.25;
    W[1][0]                            = 0.25;
    const dealii::Vector<double> rigid = linear_field(disc, W, b);
    K.vmult(Ku, rigid);
    body.constraints().set_zero(Ku);
    check_close("rigid motion: |K u| / (|K| |u|)",
                Ku.l2_norm() / (K.linfty_norm() * rigid.l2_norm()),
                0.,
                1.,
                options.field_tolerance,
                true);
    check_close("rigid motion: u^T K u / (|K| |u|^2)",
                body.strain_energy(rigid) /
                  (0.5 * K.linfty_norm() * rigid.norm_sqr()),
                0.,
                1.,
                options.energy_tolerance,
                true);

    // 3. Strain, stress and values in the cells, via the DoFHandler.
    dealii::Vector<double> nodal(disc.dof_handler().n_dofs());
    dealii::Vector<double> u_distributed = u;
    body.constraints().distribute(u_distributed);
    disc.to_dof_handler_vector(u_distributed, nodal);
    const dealii::FEValuesExtractors::Vector displacement(0);
    std::vector<dealii::Quadrature<2>> quadratures = {dealii::QGauss<2>(3),
                                                      dealii::QGauss<2>(4)};
    if (options.at_vertices)
      quadratures.emplace_back(
        dealii::QIterated<2>(dealii::QTrapezoid<1>(), 3));
    for (const auto &quadrature : quadratures)
      {
        dealii::FEValues<2>                        fe_values(disc.mapping(),
                                      disc.fe(),
                                      quadrature,
                                      dealii::update_gradients |
                                        dealii::update_values |
                                        dealii::update_quadrature_points);
        std::vector<dealii::SymmetricTensor<2, 2>> strains(quadrature.size());
        std::vector<dealii::Tensor<1, 2>>          values(quadrature.size());
        double strain_error = 0., stress_error = 0., value_error = 0.;
        for (const auto &cell : disc.dof_handler().active_cell_iterators())
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
        const std::string points =
          " at " + std::to_string(quadrature.size()) + " points per cell";
        check_close("strain error / |eps|" + points,
                    strain_error / eps.norm(),
                    0.,
                    1.,
                    options.field_tolerance,
                    true);
        check_close("stress error / |sigma|" + points,
                    stress_error / sigma.norm(),
                    0.,
                    1.,
                    options.field_tolerance,
                    true);
        check_close("value error" + points,
                    value_error,
                    0.,
                    1.,
                    options.field_tolerance,
                    true);
      }
  }
} // namespace isoimpact_tests

#endif
