// An example of a user's isogeometric program on top of isoimpact: linear
// elasticity on a NURBS quarter annulus (exact circles) with FE_NURBS and
// MappingNURBS, assembled and written like any deal.II program.
//
// The annulus 1 <= r <= 2 is held on its whole boundary and loaded by the
// body force of the displacement u = (phi, phi), phi = (r^2-1)(4-r^2) x y,
// so the exact solution is known: the program prints the L2 error and writes
// the solution to quarter_annulus.vtu (curved cells) for ParaView. Exits
// non-zero if the error exceeds 1e-2 m (it is 3.4e-3 m on 8 x 8 spans).
#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/sparse_direct.h>

#include <deal.II/numerics/data_out.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/nurbs/geometries.h>

#include <cmath>
#include <fstream>
#include <iostream>

using namespace dealii;

using namespace isoimpact;

// The exact displacement component and the body force b = -div sigma(u),
// written out for u = (phi, phi) with E = 1000 Pa, nu = 0.2, plane strain.
double
exact_phi(const Point<2> &p)
{
  const double r2 = p.square();
  return (r2 - 1.) * (4. - r2) * p[0] * p[1];
}

Tensor<1, 2>
body_force(const Point<2> &p, const ElasticMaterial &material)
{
  // Second derivatives of phi = (-r^4 + 5 r^2 - 4) x y
  //                             = -x^5 y - 2 x^3 y^3 - x y^5 + 5 x^3 y + 5 x
  //                             y^3 - 4 x y.
  const double x = p[0], y = p[1];
  const double pxx = -20. * x * x * x * y - 12. * x * y * y * y + 30. * x * y;
  const double pyy = -12. * x * x * x * y - 20. * x * y * y * y + 30. * x * y;
  const double pxy = -5. * x * x * x * x - 18. * x * x * y * y -
                     5. * y * y * y * y + 15. * x * x + 15. * y * y - 4.;
  const double lambda = material.lame_lambda(), mu = material.lame_mu();
  // div sigma_i = mu Laplace u_i + (lambda + mu) d_i (div u), u_i = phi.
  Tensor<1, 2> b;
  b[0] = -(mu * (pxx + pyy) + (lambda + mu) * (pxx + pxy));
  b[1] = -(mu * (pxx + pyy) + (lambda + mu) * (pxy + pyy));
  return b;
}

int
main()
{
  const ElasticMaterial material;

  // The geometry: a quadratic NURBS patch, refined to 8 x 8 knot spans.
  auto geometry = nurbs::quarter_annulus(1., 2.);
  geometry.patch.refine_uniformly(8);
  const DiscretizationIGA<2> disc(geometry);

  // Zero displacement on the whole boundary: zero boundary control points.
  AffineConstraints<double> constraints;
  for (const types::boundary_id id :
       {BodyGeometry::curved_boundary_id, BodyGeometry::symmetry_boundary_id})
    for (unsigned int c = 0; c < 2; ++c)
      disc.constrain_component_on_boundary(id, c, constraints);
  constraints.close();

  SparsityPattern sparsity;
  make_sparsity_pattern(disc, constraints, sparsity);
  SparseMatrix<double> stiffness(sparsity);
  assemble_stiffness_matrix(disc, material, constraints, stiffness);

  // The load vector, assembled like every other vector of the library.
  Vector<double> rhs;
  assemble_load_vector<2>(
    disc,
    [&](const Point<2> &p) {
      return body_force(p, material);
    },
    constraints,
    rhs);

  SparseDirectUMFPACK solver;
  solver.initialize(stiffness);
  Vector<double> u(disc.n_dofs());
  solver.vmult(u, rhs);
  constraints.distribute(u);

  // The L2 error, and the solution for ParaView.
  Vector<double> u_dofs(disc.dof_handler().n_dofs());
  disc.to_dof_handler_vector(u, u_dofs);
  FEValues<2>                 fe_values(disc.mapping(),
                        disc.fe(),
                        disc.cell_quadrature(),
                        update_values | update_quadrature_points |
                          update_JxW_values);
  std::vector<Vector<double>> values(fe_values.n_quadrature_points,
                                     Vector<double>(2));
  double                      error = 0.;
  for (const auto &cell : disc.dof_handler().active_cell_iterators())
    {
      fe_values.reinit(cell);
      fe_values.get_function_values(u_dofs, values);
      for (const unsigned int q : fe_values.quadrature_point_indices())
        for (unsigned int c = 0; c < 2; ++c)
          error +=
            std::pow(values[q](c) - exact_phi(fe_values.quadrature_point(q)),
                     2) *
            fe_values.JxW(q);
    }
  error = std::sqrt(error);

  DataOut<2> data_out;
  data_out.attach_dof_handler(disc.dof_handler());
  data_out.add_data_vector(
    u_dofs,
    std::vector<std::string>(2, "displacement_m"),
    DataOut<2>::type_dof_data,
    std::vector<DataComponentInterpretation::DataComponentInterpretation>(
      2,
      DataComponentInterpretation::component_is_part_of_vector));
  data_out.build_patches(disc.mapping(), 4, DataOut<2>::curved_inner_cells);
  std::ofstream out("quarter_annulus.vtu");
  data_out.write_vtu(out);

  std::cout << "nurbs_quarter_annulus: " << disc.name() << ", " << disc.n_dofs()
            << " unknowns, L2 error " << error
            << " m; solution in quarter_annulus.vtu" << std::endl;
  return error < 1e-2 ? 0 : 1;
}
