// The patch test of the stiffness (test_helpers.h: strain energy, interior
// and rigid-motion residuals, strain, stress and values in the cells for a
// field linear in the physical coordinates) over both methods, created
// through create_discretization, in plane strain and plane stress:
// - FEA, FE_Q(2) with MappingQ(2): a rectangle, a locally refined rectangle
//   (hanging nodes) and the half disk (distorted, curved cells). Tolerance
//   1e-10 relative: round-off gives 1e-13 (energy) and 3e-14 (strains) on
//   the rectangles. On the half disk the measured strain and stress errors
//   are 5e-11 and 6.5e-11: deal.II's TransfiniteInterpolationManifold gives
//   the mapping support points of a line seen from the two neighbouring
//   cells up to 3.5e-11 apart (a pull-back tolerance; dof_position keeps one
//   of them), so the linear field is linear only to ~3e-11 / h in its
//   gradient. This grows under refinement (2.6e-10 with 3 levels), hence 2
//   levels here. The boundary residual (the control) is 1.9e-4 .. 3.7e-4.
// - IGA, FE_NURBS (four patches glued C0, control points as unknowns): the
//   rectangle with degrees 2 and 3, the half disk, the half disk locally
//   refined along knot lines (degree 3), and one patch with knots graded
//   toward the contact corner (degree 3; not through the factory: the
//   multi-patch bodies refuse graded refinement; not at the cell vertices:
//   two corners of the patch have det J = 0). NURBS functions sum to one
//   and reproduce x exactly (exact geometry), so the same tolerances hold.
#include <isoimpact/discretization/discretization.h>

#include "test_helpers.h"

using namespace dealii;
using namespace isoimpact;
using namespace isoimpact_tests;

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

  for (const bool plane_strain : {true, false})
    {
      for (const auto &[name, geometry] :
           {std::make_pair("rectangle", rectangle),
            std::make_pair("rectangle with hanging nodes", rectangle_hanging),
            std::make_pair("half disk", half_disk(2))})
        check_patch_test(name,
                         create_discretization<2>(DiscretizationMethod::fea,
                                                  geometry,
                                                  2),
                         plane_strain);

      for (const auto &[name, geometry, degree] :
           {std::make_tuple("rectangle", rectangle, 2u),
            std::make_tuple("rectangle", rectangle, 3u),
            std::make_tuple("half disk", half_disk(2), 2u),
            std::make_tuple("locally refined half disk", half_disk(1, 2), 3u)})
        check_patch_test(name,
                         create_discretization<2>(DiscretizationMethod::iga,
                                                  geometry,
                                                  degree),
                         plane_strain);
      PatchTestOptions options;
      options.at_vertices = false; // det J = 0 at two corners of the patch
      check_patch_test("graded half disk",
                       graded_half_disk_iga(1, 2, 3),
                       plane_strain,
                       options);
    }
  return isoimpact_tests::report();
}
