// Cross-check of FE_NURBS + MappingNURBS with deal.II's own elements: on a
// rectangle made of one element of degree p (open knot vectors without
// interior knots, all weights 1) the NURBS functions are the tensor-product
// Bernstein polynomials, and the geometry is affine. So FEValues with
// FE_NURBS and MappingNURBS must equal FEValues with FE_Bernstein(p) and
// MappingQ(1) on the same cell: values, real-space gradients, quadrature
// points and JxW, in the cell and on all four faces (normals too), to 1e-12
// (relative to the gradient size for gradients). FE_Bernstein numbers its
// functions hierarchically (vertices, lines, interior), FE_NURBS
// lexicographically: FETools::hierarchic_to_lexicographic_numbering maps one
// to the other. Degrees 2 and 3; also for the vector element
// FESystem(FE_NURBS, 2) against FESystem(FE_Bernstein, 2).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_bernstein.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/nurbs/geometries.h>

#include <cmath>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  // The largest differences between FE_NURBS and FE_Bernstein at the points
  // of a cell or face: values, gradients (relative to 1 / h), quadrature
  // points and JxW.
  struct Differences
  {
    double value = 0., gradient = 0., point = 0., jxw = 0.;
  };

  // Adds the differences at the points where `nurbs` and `bernstein` were
  // last reinitialized (FEValues or FEFaceValues); Bernstein function h is
  // NURBS function lexicographic[h].
  template <typename FEValuesType>
  void
  accumulate(const FEValuesType              &nurbs,
             const FEValuesType              &bernstein,
             const std::vector<unsigned int> &lexicographic,
             const double                     scale,
             Differences                     &differences)
  {
    for (const unsigned int q : nurbs.quadrature_point_indices())
      {
        differences.point = std::max(differences.point,
                                     nurbs.quadrature_point(q).distance(
                                       bernstein.quadrature_point(q)));
        differences.jxw =
          std::max(differences.jxw, std::abs(nurbs.JxW(q) - bernstein.JxW(q)));
        for (unsigned int h = 0; h < lexicographic.size(); ++h)
          {
            const unsigned int l = lexicographic[h];
            differences.value    = std::max(differences.value,
                                         std::abs(nurbs.shape_value(l, q) -
                                                  bernstein.shape_value(h, q)));
            differences.gradient = std::max(
              differences.gradient,
              (nurbs.shape_grad(l, q) - bernstein.shape_grad(h, q)).norm() /
                scale);
          }
      }
  }

  void
  check_zero(const Differences &differences)
  {
    CHECK_CLOSE_ABS(differences.value, 0., 1e-12);
    CHECK_CLOSE_ABS(differences.gradient, 0., 1e-12);
    CHECK_CLOSE_ABS(differences.point, 0., 1e-12);
    CHECK_CLOSE_ABS(differences.jxw, 0., 1e-12);
  }

  void
  compare(const unsigned int degree)
  {
    std::cout << "degree " << degree << std::endl;
    const Point<2>             corner1(-1., 0.5), corner2(2., 1.75);
    const DiscretizationIGA<2> iga(nurbs::rectangle(corner1, corner2, degree));
    CHECK_TRUE(iga.triangulation().n_active_cells() == 1);

    const FE_Bernstein<2> bernstein(degree);
    const FESystem<2>     bernstein_system(bernstein, 2);
    const MappingQ<2>     mapping_q(1);
    const auto           &fe_nurbs = iga.fe().base_element(0);
    CHECK_TRUE(fe_nurbs.n_dofs_per_cell() == bernstein.n_dofs_per_cell());

    // lexicographic[h] = lexicographic index of hierarchic function h.
    const std::vector<unsigned int> lexicographic =
      FETools::hierarchic_to_lexicographic_numbering<2>(degree);

    const auto dof_cell = iga.dof_handler().begin_active();
    // The scalar elements are not the DoFHandler's: FEValues of them are
    // reinitialized on the triangulation cell.
    const typename Triangulation<2>::cell_iterator cell(dof_cell);
    const double                                   scale =
      1. / std::min(corner2[0] - corner1[0], corner2[1] - corner1[1]);

    // Cell.
    {
      const QGauss<2>   quadrature(degree + 2);
      const UpdateFlags flags = update_values | update_gradients |
                                update_quadrature_points | update_JxW_values;
      FEValues<2> nurbs_values(iga.mapping(), fe_nurbs, quadrature, flags);
      FEValues<2> bernstein_values(mapping_q, bernstein, quadrature, flags);
      FEValues<2> nurbs_system(iga.mapping(),
                               iga.fe(),
                               quadrature,
                               update_values | update_gradients);
      FEValues<2> bernstein_system_values(mapping_q,
                                          bernstein_system,
                                          quadrature,
                                          update_values | update_gradients);
      nurbs_values.reinit(cell);
      bernstein_values.reinit(cell);
      nurbs_system.reinit(dof_cell);
      bernstein_system_values.reinit(cell);
      Differences cell_differences;
      accumulate(nurbs_values,
                 bernstein_values,
                 lexicographic,
                 scale,
                 cell_differences);
      double system_error = 0.;
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          // Vector elements: component c of system function i.
          for (unsigned int i = 0; i < bernstein_system.n_dofs_per_cell(); ++i)
            {
              const auto [c, h] = bernstein_system.system_to_component_index(i);
              const unsigned int j =
                iga.fe().component_to_system_index(c, lexicographic[h]);
              system_error = std::max(
                system_error,
                std::abs(
                  nurbs_system.shape_value_component(j, q, c) -
                  bernstein_system_values.shape_value_component(i, q, c)) +
                  (nurbs_system.shape_grad_component(j, q, c) -
                   bernstein_system_values.shape_grad_component(i, q, c))
                      .norm() /
                    scale);
            }
        }
      check_zero(cell_differences);
      CHECK_CLOSE_ABS(system_error, 0., 1e-12);
    }

    // Faces.
    {
      const QGauss<1>   quadrature(degree + 2);
      const UpdateFlags flags = update_values | update_gradients |
                                update_quadrature_points | update_JxW_values |
                                update_normal_vectors;
      FEFaceValues<2> nurbs_values(iga.mapping(), fe_nurbs, quadrature, flags);
      FEFaceValues<2> bernstein_values(mapping_q, bernstein, quadrature, flags);
      Differences     face_differences;
      double          normal_error = 0.;
      for (const unsigned int f : cell->face_indices())
        {
          nurbs_values.reinit(cell, f);
          bernstein_values.reinit(cell, f);
          accumulate(nurbs_values,
                     bernstein_values,
                     lexicographic,
                     scale,
                     face_differences);
          for (const unsigned int q : nurbs_values.quadrature_point_indices())
            normal_error = std::max(normal_error,
                                    (nurbs_values.normal_vector(q) -
                                     bernstein_values.normal_vector(q))
                                      .norm());
        }
      check_zero(face_differences);
      CHECK_CLOSE_ABS(normal_error, 0., 1e-12);
    }

    // Mapping functions: unit <-> real round trip.
    {
      const Point<2> unit(0.3, 0.8);
      const Point<2> real =
        iga.mapping().transform_unit_to_real_cell(cell, unit);
      CHECK_CLOSE_ABS(real.distance(
                        mapping_q.transform_unit_to_real_cell(cell, unit)),
                      0.,
                      1e-12);
      CHECK_CLOSE_ABS(
        iga.mapping().transform_real_to_unit_cell(cell, real).distance(unit),
        0.,
        1e-12);
    }
  }
} // namespace

int
main()
{
  compare(2);
  compare(3);
  return isoimpact_tests::report();
}
