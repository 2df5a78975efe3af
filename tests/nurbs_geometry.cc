// Geometries: exact arcs, areas by Gauss quadrature of det J, det J > 0,
// rational basis per element (sums, gradients against finite differences,
// consistency with NURBSPatch::jacobian).
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/nurbs/geometries.h>

#include <random>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;
using dealii::Point;

namespace
{
  struct AreaResult
  {
    double area                  = 0.;
    double min_det               = 1e300;
    double max_jacobian_mismatch = 0.;
    double max_sum_error         = 0.;
    double max_fd_error          = 0.;
  };

  // Area = sum over elements and Gauss points of det(dX/dreference).
  AreaResult
  measure(const NURBSPatch<2> &patch, const unsigned int n_gauss)
  {
    AreaResult                        result;
    const dealii::QGauss<2>           quadrature(n_gauss);
    std::vector<double>               R, Rp;
    std::vector<dealii::Tensor<1, 2>> dR, dRp;
    std::vector<unsigned int>         indices;
    for (unsigned int e = 0; e < patch.n_elements(); ++e)
      {
        patch.element_control_points(e, indices);
        const auto box = patch.element_parameter_box(e);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const Point<2> &xi = quadrature.point(q);
            patch.element_rational_basis(e, xi, R, dR);
            dealii::Tensor<2, 2> J;
            double               sum = 0.;
            dealii::Tensor<1, 2> grad_sum;
            for (unsigned int a = 0; a < R.size(); ++a)
              {
                J += dealii::outer_product(patch.control_points()[indices[a]],
                                           dR[a]);
                sum += R[a];
                grad_sum += dR[a];
              }
            const double det = dealii::determinant(J);
            result.area += det * quadrature.weight(q);
            result.min_det       = std::min(result.min_det, det);
            result.max_sum_error = std::max(
              {result.max_sum_error, std::abs(sum - 1.), grad_sum.norm()});

            // Same Jacobian from NURBSPatch::jacobian (parameter derivative)
            // times the span lengths.
            Point<2> parameter;
            for (unsigned int d = 0; d < 2; ++d)
              parameter[d] =
                box.first[d] + xi[d] * (box.second[d] - box.first[d]);
            const auto J_parameter = patch.jacobian(parameter);
            for (unsigned int i = 0; i < 2; ++i)
              for (unsigned int j = 0; j < 2; ++j)
                result.max_jacobian_mismatch =
                  std::max(result.max_jacobian_mismatch,
                           std::abs(J_parameter[i][j] *
                                      (box.second[j] - box.first[j]) -
                                    J[i][j]) /
                             J.norm());

            // Gradients against central differences in reference coordinates.
            if (q % 7 == 0)
              for (unsigned int d = 0; d < 2; ++d)
                {
                  const double h  = 1e-6;
                  Point<2>     xp = xi, xm = xi;
                  xp[d] += h;
                  xm[d] -= h;
                  std::vector<double> Rm;
                  patch.element_rational_basis(e, xp, Rp, dRp);
                  patch.element_rational_basis(e, xm, Rm, dRp);
                  double scale = 0.;
                  for (unsigned int a = 0; a < R.size(); ++a)
                    scale = std::max(scale, dR[a].norm());
                  for (unsigned int a = 0; a < R.size(); ++a)
                    result.max_fd_error =
                      std::max(result.max_fd_error,
                               std::abs((Rp[a] - Rm[a]) / (2 * h) - dR[a][d]) /
                                 scale);
                }
          }
      }
    return result;
  }

  void
  check_area(const std::string   &name,
             const NURBSPatch<2> &patch,
             const double         expected_area)
  {
    std::cout << name << ": " << patch.n_elements() << " elements" << std::endl;
    const AreaResult r = measure(patch, 12);
    CHECK_CLOSE(r.area, expected_area, 1e-13);
    CHECK_TRUE(r.min_det > 0.);
    std::cout << "     min det J (reference cell) = " << r.min_det << std::endl;
    CHECK_CLOSE_ABS(r.max_jacobian_mismatch, 0., 1e-13);
    CHECK_CLOSE_ABS(r.max_sum_error, 0., 1e-13);
    CHECK_CLOSE_ABS(r.max_fd_error, 0., 1e-7);
  }

  // max |(|X(xi) - center| - R)| / R over samples of side `face`.
  double
  arc_error(const NURBSPatch<2> &patch,
            const unsigned int   face,
            const Point<2>      &center,
            const double         radius)
  {
    double max_error = 0.;
    for (unsigned int i = 0; i <= 1000; ++i)
      {
        Point<2>           xi;
        const unsigned int d = face / 2;
        xi[d]                = (face % 2 == 0) ? 0. : 1.;
        xi[1 - d]            = i / 1000.;
        max_error =
          std::max(max_error,
                   std::abs(patch.evaluate(xi).distance(center) - radius) /
                     radius);
      }
    return max_error;
  }
} // namespace

int
main()
{
  const double   R = 0.7;
  const Point<2> c(0.3, 2.);
  {
    std::cout << "half disk" << std::endl;
    auto        geometry = half_disk(R, c);
    const auto &patch    = geometry.patch;
    CHECK_TRUE(geometry.side_kinds[half_disk_sides::lower_arc] ==
               SideKind::arc);
    CHECK_TRUE(geometry.side_kinds[half_disk_sides::upper_arc] ==
               SideKind::arc);
    CHECK_TRUE(geometry.sides_of_kind(SideKind::symmetry) ==
               std::vector<unsigned int>({0, 3}));
    CHECK_CLOSE_ABS(arc_error(patch, half_disk_sides::lower_arc, c, R),
                    0.,
                    1e-13);
    CHECK_CLOSE_ABS(arc_error(patch, half_disk_sides::upper_arc, c, R),
                    0.,
                    1e-13);
    // The cut sides lie on x = c_x and cover [c_y - R, c_y + R].
    double max_cut_error = 0.;
    for (unsigned int i = 0; i <= 100; ++i)
      {
        max_cut_error = std::max(
          {max_cut_error,
           std::abs(patch.evaluate(Point<2>(0., i / 100.))[0] - c[0]),
           std::abs(patch.evaluate(Point<2>(i / 100., 1.))[0] - c[0])});
      }
    CHECK_CLOSE_ABS(max_cut_error, 0., 1e-15);
    const Point<2> contact = patch.evaluate(geometry.contact_parameter);
    CHECK_TRUE(geometry.has_contact_point);
    CHECK_CLOSE_ABS(contact.distance(Point<2>(c[0], c[1] - R)), 0., 1e-15);
    CHECK_CLOSE_ABS(geometry.contact_point.distance(contact), 0., 1e-15);
    CHECK_CLOSE_ABS(
      patch.evaluate(Point<2>(1., 1.)).distance(Point<2>(c[0], c[1] + R)),
      0.,
      1e-15);
    CHECK_CLOSE_ABS(patch.evaluate(Point<2>(0., 1.)).distance(c), 0., 1e-15);
    // At the contact corner the two sides meet at a right angle, J regular.
    CHECK_TRUE(patch.jacobian(Point<2>(0., 0.)).determinant() > 0.);

    check_area("half disk, 1 element", patch, M_PI * R * R / 2.);
    auto refined = patch;
    refined.refine_uniformly(4);
    check_area("half disk, 4x4", refined, M_PI * R * R / 2.);
    refined.refine_graded(0, 0, 3, 2.);
    refined.refine_graded(1, 0, 3, 2.);
    check_area("half disk, graded toward the contact point",
               refined,
               M_PI * R * R / 2.);
    CHECK_CLOSE_ABS(arc_error(refined, half_disk_sides::lower_arc, c, R),
                    0.,
                    1e-13);
  }
  {
    std::cout << "full disk" << std::endl;
    auto geometry = full_disk(R, c);
    for (unsigned int f = 0; f < 4; ++f)
      CHECK_CLOSE_ABS(arc_error(geometry.patch, f, c, R), 0., 1e-13);
    check_area("full disk, 1 element", geometry.patch, M_PI * R * R);
    geometry.patch.refine_uniformly(3);
    check_area("full disk, 3x3", geometry.patch, M_PI * R * R);
  }
  {
    std::cout << "quarter annulus" << std::endl;
    const double r1 = 0.4, r2 = 1.1;
    auto         geometry = quarter_annulus(r1, r2, c);
    CHECK_CLOSE_ABS(arc_error(geometry.patch, 0, c, r1), 0., 1e-13);
    CHECK_CLOSE_ABS(arc_error(geometry.patch, 1, c, r2), 0., 1e-13);
    check_area("quarter annulus",
               geometry.patch,
               M_PI * (r2 * r2 - r1 * r1) / 4.);
    geometry.patch.refine_uniformly(2);
    check_area("quarter annulus, 2x2",
               geometry.patch,
               M_PI * (r2 * r2 - r1 * r1) / 4.);
  }
  {
    std::cout << "rectangle" << std::endl;
    auto geometry = rectangle(Point<2>(2., 1.), Point<2>(-1., 0.5), 3);
    check_area("rectangle, cubic", geometry.patch, 1.5);
    CHECK_CLOSE_ABS(geometry.patch.evaluate(Point<2>(0.25, 0.5))
                      .distance(Point<2>(-0.25, 0.75)),
                    0.,
                    1e-15);
  }
  return isoimpact_tests::report();
}
