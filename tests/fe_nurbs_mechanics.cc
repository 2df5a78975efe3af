// DiscretizationIGA with the library's mechanics (assembly, ElasticBody):
// 1. Total mass of the half disk (R = 4, centre (0, 4), rho = 1.3) with
//    consistent, row-sum and HRZ mass equals rho pi R^2 / 2 (the NURBS
//    geometry is exact; the cell quadrature of DiscretizationIGA is accurate
//    enough for the rational det J, see get_cell_quadrature) to 1e-12
//    relative, created through create_discretization("iga", ...) (four
//    patches glued C0) with uniform and locally refined knots, degrees 2 and
//    3, and as one patch with knots graded toward the contact corner. All
//    lumped entries are positive (NURBS functions are non-negative, so row sums
//    are; HRZ scales positive diagonals).
// 2. The patch test (rectangle, half disk, locally refined and graded half
//    disk) is in tests/patch_test.cc, shared with FEA.
// 3. Interface details: n_dofs = 2 n_control_points, dof_position =
//    control point, constraints on the symmetry boundary fix the control
//    points of the cut, boundary segments of the arc reproduce the circle.
#include <deal.II/base/numbers.h>


#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "test_helpers.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  const double radius  = isoimpact_tests::half_disk_radius;
  const double density = 1.3;
  using isoimpact_tests::half_disk;
  using isoimpact_tests::half_disk_center;

  using Factory = std::function<std::unique_ptr<Discretization<2>>()>;

  Factory
  multipatch(const BodyGeometry &geometry, const unsigned int degree)
  {
    return [=]() {
      return create_discretization<2>(DiscretizationMethod::iga,
                                      geometry,
                                      degree);
    };
  }

  // One patch over the half disk with knots graded toward the contact
  // corner.
  Factory
  graded_single_patch(const unsigned int global_refinements,
                      const unsigned int layers,
                      const unsigned int degree)
  {
    return [=]() {
      return isoimpact_tests::graded_half_disk_iga(global_refinements,
                                                   layers,
                                                   degree);
    };
  }

  void
  check_mass(const Factory &make)
  {
    const double    exact = density * numbers::PI * radius * radius / 2.;
    ElasticMaterial material;
    material.density = density;
    for (const MassScheme scheme :
         {MassScheme::consistent, MassScheme::row_sum, MassScheme::hrz})
      {
        const ElasticBody<2> body("disk",
                                  make(),
                                  material,
                                  scheme,
                                  {},
                                  Tensor<1, 2>());
        std::cout << "mass, " << to_string(scheme) << ", "
                  << body.discretization().name() << std::endl;
        CHECK_CLOSE(body.total_mass(), exact, 1e-12);
        if (scheme == MassScheme::consistent)
          CHECK_CLOSE(integrate_mass(body.discretization(), density),
                      exact,
                      1e-12);
        else
          {
            const Vector<double> lumped =
              assemble_lumped_mass(body.discretization(),
                                   density,
                                   scheme,
                                   body.constraints());
            double minimum = lumped(0), sum = 0.;
            for (const double m : lumped)
              {
                minimum = std::min(minimum, m);
                sum += m;
              }
            CHECK_TRUE(minimum > 0.);
            CHECK_CLOSE(sum, 2. * exact, 1e-12);
          }
      }
  }

  void
  check_interface()
  {
    std::cout << "interface" << std::endl;
    const DiscretizationIGA<2> discretization(half_disk(1), 2);
    const auto                &patches = discretization.patches();
    CHECK_TRUE(discretization.n_dofs() == 2 * patches.n_control_points());
    double position_error = 0.;
    for (types::global_dof_index i = 0; i < discretization.n_dofs(); ++i)
      position_error = std::max(position_error,
                                discretization.dof_position(i).distance(
                                  patches.control_points()[i / 2]));
    CHECK_CLOSE_ABS(position_error, 0., 0.);

    // Roller on the cut: the x components of the control points on x = 0.
    AffineConstraints<double> constraints;
    discretization.constrain_component_on_boundary(
      BodyGeometry::symmetry_boundary_id,
      0,
      constraints);
    unsigned int n_on_cut = 0;
    bool         all_x    = true;
    for (unsigned int a = 0; a < patches.n_control_points(); ++a)
      if (std::abs(patches.control_points()[a][0]) < 1e-12)
        {
          ++n_on_cut;
          all_x = all_x && constraints.is_constrained(2 * a) &&
                  !constraints.is_constrained(2 * a + 1);
        }
    CHECK_TRUE(all_x);
    CHECK_TRUE(constraints.n_constraints() == n_on_cut);

    // The arc segments (3 patches with 2 spans each on the arc) lie on the
    // circle, their ends are shared (the two ends of the arc meet the
    // symmetry cut, where the surface continues in its mirror image), and
    // normal_orientation gives the outward normal.
    const auto segments =
      discretization.boundary_segments(BodyGeometry::curved_boundary_id);
    CHECK_TRUE(segments.size() == 3 * 2);
    double              radius_error = 0., normal_error = 0.;
    unsigned int        n_free_ends = 0;
    std::vector<double> r, dr;
    for (const auto &segment : segments)
      {
        n_free_ends += segment.free_end[0] + segment.free_end[1];
        for (unsigned int k = 0; k <= 10; ++k)
          {
            evaluate_segment_basis(segment, k / 10., r, dr);
            Point<2>     x;
            Tensor<1, 2> tangent;
            for (unsigned int n = 0; n < r.size(); ++n)
              {
                x += r[n] * segment.node_positions[n];
                tangent += dr[n] * segment.node_positions[n];
              }
            radius_error =
              std::max(radius_error,
                       std::abs(x.distance(half_disk_center) - radius));
            Tensor<1, 2> normal({tangent[1], -tangent[0]});
            normal *= segment.normal_orientation / normal.norm();
            normal_error =
              std::max(normal_error,
                       (normal - (x - half_disk_center) / radius).norm());
          }
      }
    CHECK_CLOSE_ABS(radius_error, 0., 1e-13);
    CHECK_CLOSE_ABS(normal_error, 0., 1e-13);
    CHECK_TRUE(n_free_ends == 0);
    CHECK_TRUE(
      discretization.boundary_segments(BodyGeometry::symmetry_boundary_id)
        .size() == 3 * 2);
  }
} // namespace

int
main()
{
  check_mass(multipatch(half_disk(1), 2));
  check_mass(multipatch(half_disk(3), 2));
  check_mass(multipatch(half_disk(2), 3));
  check_mass(graded_single_patch(2, 3, 2));

  // Local refinement of the glued patches along knot lines: 2 passes halve
  // the spans near the contact point (0, 0) twice (smallest cell diameter
  // at the contact point a quarter of the uniform one, to 5 %: halving
  // in the rational parameter is not halving the arc length), interfaces stay
  // conforming (MultiPatch refuses others), mass as before (the patch test is
  // in tests/patch_test.cc).
  {
    const auto uniform =
      create_discretization<2>(DiscretizationMethod::iga, half_disk(2), 2);
    const auto local =
      create_discretization<2>(DiscretizationMethod::iga, half_disk(2, 2), 2);
    // The diameter of the cell at the contact point (0, 0).
    const auto smallest_near_contact = [](const Discretization<2> &d) {
      for (const auto &cell : d.triangulation().active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          if (cell->vertex(v).norm() < 1e-12)
            return cell->diameter();
      return 0.;
    };
    std::cout << "local refinement: " << local->name() << std::endl;
    CHECK_TRUE(local->triangulation().n_active_cells() >
               uniform->triangulation().n_active_cells());
    CHECK_CLOSE(smallest_near_contact(*local),
                smallest_near_contact(*uniform) / 4.,
                0.05);
  }
  check_mass(multipatch(half_disk(2, 2), 2));

  check_interface();
  return isoimpact_tests::report();
}
