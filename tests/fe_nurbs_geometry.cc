// FE_NURBS and MappingNURBS on the half disk (R = 4, centre (0, 4)):
// 1. The sum of JxW over all cells equals the exact area pi R^2 / 2: the
//    NURBS geometry is the exact half disk, and the Gauss rule of p+1 points
//    is not exact for the rational det J, so several quadrature orders and
//    refinements are used; with (p+1)+6 points per direction on 4x4 spans
//    the quadrature error is below 1e-14 relative (tolerance 1e-13).
// 2. FEFaceValues on the arc faces (boundary id 0): every quadrature point
//    at distance R from the centre (1e-13 relative), the normal is the
//    radial direction (1e-13), and the sum of face JxW is the half
//    circumference pi R (quadrature accurate to 1e-13 with 12 points).
//    On the symmetry faces (id 1) the points have x = 0 and the normal is
//    (-1, 0); their JxW sum to the diameter 2R.
// 3. Partition of unity: at every cell quadrature point the FE_NURBS shape
//    values sum to 1 and the gradients to 0 (1e-13 relative to the sum of
//    the gradients' norms: near the corners E and O, where det J -> 0, the
//    gradients are large and so is their round-off), also for the
//    FESystem(FE_NURBS, 2) components.
// 4. Gradients: interpolating x (the control point coordinates, since the
//    rational basis reproduces the geometry) gives grad x = identity at the
//    quadrature points (1e-12), which checks the covariant push-forward.
// 5. Cell similarity: two cells that are translations of each other must
//    not reuse data (MappingNURBS returns invalid_next_cell): repeated
//    reinit on cells in different order gives identical results.
#include <deal.II/base/numbers.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/fe/fe_nurbs.h>
#include <isoimpact/fe/mapping_nurbs.h>
#include <isoimpact/nurbs/geometries.h>

#include <cmath>
#include <memory>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  const double   radius = 4.;
  const Point<2> center(0., 4.);
  const double   pi = numbers::PI;

  BodyGeometry
  half_disk(const unsigned int global_refinements)
  {
    BodyGeometry body;
    body.shape              = BodyGeometry::Shape::half_disk;
    body.center             = center;
    body.radius             = radius;
    body.global_refinements = global_refinements;
    return body;
  }

  void
  check_area_and_partition_of_unity(const unsigned int degree,
                                    const unsigned int refinements,
                                    const unsigned int extra_points)
  {
    std::cout << "half disk, degree " << degree << ", " << refinements
              << " refinements, " << extra_points << " extra points"
              << std::endl;
    const DiscretizationIGA<2> discretization(half_disk(refinements), degree);
    const auto                &mapping       = discretization.mapping();
    const auto                &fe_system     = discretization.fe();
    const auto                &fe            = fe_system.base_element(0);
    const auto                &triangulation = discretization.triangulation();

    const QGauss<2> quadrature(degree + 1 + extra_points);
    FEValues<2>     fe_values(mapping,
                          fe,
                          quadrature,
                          update_values | update_gradients | update_JxW_values |
                            update_quadrature_points);
    FEValues<2>     system_values(mapping,
                              fe_system,
                              quadrature,
                              update_values | update_gradients);

    const auto &patches    = discretization.patches();
    double      area       = 0.;
    double max_value_error = 0., max_gradient_error = 0., max_system_error = 0.,
           max_identity_error = 0.;
    std::vector<unsigned int> control_points;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      {
        // The scalar element is not the DoFHandler's: reinit on the
        // triangulation cell.
        fe_values.reinit(typename Triangulation<2>::cell_iterator(cell));
        system_values.reinit(cell);
        patches.element_control_points(cell->user_index(), control_points);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            area += fe_values.JxW(q);
            double       sum = 0.;
            Tensor<1, 2> gradient_sum;
            double       gradient_scale = 0.;
            Tensor<2, 2> grad_x;
            for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
              {
                sum += fe_values.shape_value(i, q);
                gradient_sum += fe_values.shape_grad(i, q);
                gradient_scale += fe_values.shape_grad(i, q).norm();
                const Point<2> &P = patches.control_points()[control_points[i]];
                for (unsigned int a = 0; a < 2; ++a)
                  grad_x[a] += P[a] * fe_values.shape_grad(i, q);
              }
            max_value_error    = std::max(max_value_error, std::abs(sum - 1.));
            max_gradient_error = std::max(max_gradient_error,
                                          gradient_sum.norm() / gradient_scale);
            max_identity_error =
              std::max(max_identity_error,
                       (grad_x - unit_symmetric_tensor<2>()).norm());
            for (unsigned int c = 0; c < 2; ++c)
              {
                double s = 0.;
                for (unsigned int i = 0; i < fe_system.n_dofs_per_cell(); ++i)
                  s += system_values.shape_value_component(i, q, c);
                max_system_error = std::max(max_system_error, std::abs(s - 1.));
              }
          }
      }
    CHECK_CLOSE(area, pi * radius * radius / 2., 1e-13);
    CHECK_CLOSE_ABS(max_value_error, 0., 1e-13);
    CHECK_CLOSE_ABS(max_gradient_error, 0., 1e-13);
    CHECK_CLOSE_ABS(max_system_error, 0., 1e-13);
    CHECK_CLOSE_ABS(max_identity_error, 0., 1e-12);
    CHECK_TRUE(triangulation.n_active_cells() == patches.n_elements());
  }

  void
  check_faces(const unsigned int degree, const unsigned int refinements)
  {
    std::cout << "faces, degree " << degree << ", " << refinements
              << " refinements" << std::endl;
    const DiscretizationIGA<2> discretization(half_disk(refinements), degree);
    const QGauss<1>            quadrature(12);
    FEFaceValues<2>            fe_face_values(discretization.mapping(),
                                   discretization.fe(),
                                   quadrature,
                                   update_values | update_quadrature_points |
                                     update_normal_vectors | update_JxW_values);
    double max_radius_error = 0., max_normal_error = 0., max_cut_error = 0.,
           arc_length = 0., cut_length = 0.;
    unsigned int n_arc_faces = 0, n_cut_faces = 0;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            fe_face_values.reinit(cell, f);
            const auto id = cell->face(f)->boundary_id();
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              {
                const Point<2> &x = fe_face_values.quadrature_point(q);
                if (id == BodyGeometry::curved_boundary_id)
                  {
                    max_radius_error =
                      std::max(max_radius_error,
                               std::abs(x.distance(center) - radius) / radius);
                    const Tensor<1, 2> radial =
                      (x - center) / x.distance(center);
                    max_normal_error = std::max(
                      max_normal_error,
                      (fe_face_values.normal_vector(q) - radial).norm());
                    arc_length += fe_face_values.JxW(q);
                  }
                else if (id == BodyGeometry::symmetry_boundary_id)
                  {
                    max_cut_error = std::max(max_cut_error, std::abs(x[0]));
                    Tensor<1, 2> outward;
                    outward[0]       = -1.;
                    max_normal_error = std::max(
                      max_normal_error,
                      (fe_face_values.normal_vector(q) - outward).norm());
                    cut_length += fe_face_values.JxW(q);
                  }
              }
            (id == BodyGeometry::curved_boundary_id ? n_arc_faces :
                                                      n_cut_faces)++;
          }
    CHECK_TRUE(n_arc_faces == n_cut_faces && n_arc_faces > 0);
    CHECK_CLOSE_ABS(max_radius_error, 0., 1e-13);
    CHECK_CLOSE_ABS(max_normal_error, 0., 1e-13);
    CHECK_CLOSE_ABS(max_cut_error, 0., 1e-13);
    CHECK_CLOSE(arc_length, pi * radius, 1e-13);
    CHECK_CLOSE(cut_length, 2. * radius, 1e-13);
  }

  // Two visits of all cells in different orders must agree exactly.
  void
  check_no_reuse()
  {
    std::cout << "cell similarity" << std::endl;
    const DiscretizationIGA<2> discretization(half_disk(2), 2);
    const QGauss<2>            quadrature(3);
    FEValues<2>                fe_values(discretization.mapping(),
                          discretization.fe(),
                          quadrature,
                          update_values | update_gradients | update_JxW_values);
    std::vector<typename DoFHandler<2>::active_cell_iterator> cells;
    for (const auto &cell :
         discretization.dof_handler().active_cell_iterators())
      cells.push_back(cell);
    std::vector<double> forward(cells.size()), backward(cells.size());
    for (unsigned int pass = 0; pass < 2; ++pass)
      for (unsigned int k = 0; k < cells.size(); ++k)
        {
          const unsigned int c = (pass == 0) ? k : cells.size() - 1 - k;
          fe_values.reinit(cells[c]);
          double s = 0.;
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            for (unsigned int i = 0; i < fe_values.dofs_per_cell; ++i)
              s += fe_values.JxW(q) * (fe_values.shape_value(i, q) +
                                       fe_values.shape_grad(i, q).norm());
          (pass == 0 ? forward : backward)[c] = s;
        }
    double difference = 0.;
    for (unsigned int c = 0; c < cells.size(); ++c)
      difference = std::max(difference, std::abs(forward[c] - backward[c]));
    CHECK_CLOSE_ABS(difference, 0., 1e-14);
  }
} // namespace

int
main()
{
  check_area_and_partition_of_unity(2, 0, 8);
  check_area_and_partition_of_unity(2, 2, 6);
  check_area_and_partition_of_unity(3, 2, 6);
  check_faces(2, 0);
  check_faces(2, 2);
  check_faces(3, 1);
  check_no_reuse();
  return isoimpact_tests::report();
}
