// NURBSPatch<3,3> (extruded quarter annulus: volume, refinement) and
// NURBSPatch<2,3> (half disk in a tilted plane: area).
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/nurbs/geometries.h>

#include <random>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;
using dealii::Point;

namespace
{
  template <int dim>
  double
  measure(const NURBSPatch<dim, 3> &patch)
  {
    const dealii::QGauss<dim>           quadrature(10);
    std::vector<double>                 R;
    std::vector<dealii::Tensor<1, dim>> dR;
    double                              result = 0.;
    for (unsigned int e = 0; e < patch.n_elements(); ++e)
      {
        const auto indices = patch.element_control_points(e);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            patch.element_rational_basis(e, quadrature.point(q), R, dR);
            dealii::DerivativeForm<1, dim, 3> J;
            for (unsigned int a = 0; a < R.size(); ++a)
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int j = 0; j < dim; ++j)
                  J[i][j] += patch.control_points()[indices[a]][i] * dR[a][j];
            result += J.determinant() * quadrature.weight(q);
          }
      }
    return result;
  }

  template <int dim>
  double
  geometry_change(const NURBSPatch<dim, 3> &before,
                  const NURBSPatch<dim, 3> &after)
  {
    std::mt19937                           rng(5);
    std::uniform_real_distribution<double> unit(0., 1.);
    double                                 max_change = 0.;
    for (unsigned int i = 0; i < 300; ++i)
      {
        Point<dim> xi;
        for (unsigned int d = 0; d < dim; ++d)
          xi[d] = unit(rng);
        max_change = std::max(max_change,
                              before.evaluate(xi).distance(after.evaluate(xi)));
      }
    return max_change;
  }
} // namespace

int
main()
{
  // Quarter annulus r in [1, 2] extruded to z in [0, 0.5].
  {
    const auto            annulus = quarter_annulus(1., 2.).patch;
    const double          H       = 0.5;
    std::vector<Point<3>> points;
    std::vector<double>   weights;
    for (unsigned int k = 0; k < 2; ++k)
      for (unsigned int a = 0; a < annulus.n_control_points(); ++a)
        {
          const Point<2> &p = annulus.control_points()[a];
          points.emplace_back(p[0], p[1], k * H);
          weights.push_back(annulus.weights()[a]);
        }
    const NURBSPatch<3, 3> solid({{annulus.knot_vector(0),
                                   annulus.knot_vector(1),
                                   KnotVector({0, 0, 1, 1}, 1)}},
                                 points,
                                 weights);
    const double           volume = M_PI * (4. - 1.) / 4. * H;
    CHECK_CLOSE(measure(solid), volume, 1e-13);
    auto refined = solid;
    refined.k_refine(1, 2);
    refined.refine_graded(2, 0, 2, 2.);
    CHECK_TRUE(refined.n_elements() == 2 * 2 * 4);
    CHECK_TRUE(refined.n_functions_per_element() == 4 * 4 * 3);
    CHECK_CLOSE_ABS(geometry_change(solid, refined), 0., 1e-13);
    CHECK_CLOSE(measure(refined), volume, 1e-13);
    // a point on the outer arc side (face 3)
    const Point<3> x = refined.evaluate(Point<3>(1., 0.3, 0.7));
    CHECK_CLOSE(std::hypot(x[0], x[1]), 2., 1e-14);
    CHECK_CLOSE(x[2], 0.7 * H, 1e-14);
    CHECK_TRUE(refined.side_control_points(5).size() == 5 * 5);
  }
  // Half disk of radius 0.8 in the plane spanned by (1,0,0), (0,cos a, sin a).
  {
    const auto            disk = half_disk(0.8).patch;
    const double          a    = 0.3;
    std::vector<Point<3>> points;
    for (const auto &p : disk.control_points())
      points.emplace_back(p[0], p[1] * std::cos(a), p[1] * std::sin(a));
    NURBSPatch<2, 3> surface(disk.knot_vectors(), points, disk.weights());
    surface.refine_uniformly(3);
    CHECK_CLOSE(measure(surface), M_PI * 0.64 / 2., 1e-13);
    CHECK_CLOSE(surface.evaluate(Point<2>(0.4, 0.)).norm(), 0.8, 1e-14);
  }
  return isoimpact_tests::report();
}
