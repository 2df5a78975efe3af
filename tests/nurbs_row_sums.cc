// Integrals of the basis functions of a straight 1D open uniform quadratic
// B-spline patch in the plane (row sums of the consistent mass matrix for
// unit density): h/3, 2h/3, h, ..., h, 2h/3, h/3 (h = element length).
#include <deal.II/base/quadrature_lib.h>

#include <isoimpact/nurbs/patch.h>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;
using dealii::Point;

int
main()
{
  const unsigned int n_elements = 6;
  const double       h          = 0.25;
  const KnotVector   kv =
    KnotVector::uniform(2, n_elements, 1., 1. + n_elements * h);
  // Control points at the Greville abscissae on the line (3, 1) + s (0.6,
  // 0.8): arc length = parameter - 1, an affine map with |dX/du| = 1.
  std::vector<Point<2>> points;
  for (unsigned int i = 0; i < kv.n_basis_functions(); ++i)
    {
      const double greville =
        0.5 * (kv.knots()[i + 1] + kv.knots()[i + 2]) - 1.;
      points.emplace_back(3. + 0.6 * greville, 1. + 0.8 * greville);
    }
  const NURBSPatch<1, 2> patch({{kv}}, points);

  std::vector<double>               integrals(patch.n_control_points(), 0.);
  const dealii::QGauss<1>           quadrature(3);
  std::vector<double>               R;
  std::vector<dealii::Tensor<1, 1>> dR;
  double                            length = 0.;
  for (unsigned int e = 0; e < patch.n_elements(); ++e)
    {
      const auto indices = patch.element_control_points(e);
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        {
          patch.element_rational_basis(e, quadrature.point(q), R, dR);
          dealii::Tensor<1, 2> tangent; // dX / dreference
          for (unsigned int a = 0; a < R.size(); ++a)
            tangent += dR[a][0] * patch.control_points()[indices[a]];
          const double JxW = tangent.norm() * quadrature.weight(q);
          length += JxW;
          for (unsigned int a = 0; a < R.size(); ++a)
            integrals[indices[a]] += R[a] * JxW;
        }
    }
  CHECK_CLOSE(length, n_elements * h, 1e-14);
  CHECK_CLOSE(integrals[0], h / 3., 1e-14);
  CHECK_CLOSE(integrals[1], 2. * h / 3., 1e-14);
  for (unsigned int i = 2; i + 2 < integrals.size(); ++i)
    CHECK_CLOSE(integrals[i], h, 1e-14);
  CHECK_CLOSE(integrals[integrals.size() - 2], 2. * h / 3., 1e-14);
  CHECK_CLOSE(integrals.back(), h / 3., 1e-14);
  return isoimpact_tests::report();
}
