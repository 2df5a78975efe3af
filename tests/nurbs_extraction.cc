// Bezier extraction: C^e B reproduces the B-spline basis on each span, in 1D
// and for the tensor-product operators of a patch.
#include <isoimpact/nurbs/geometries.h>

#include <random>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;

namespace
{
  double
  max_extraction_error(const KnotVector &kv)
  {
    std::mt19937                           rng(7);
    std::uniform_real_distribution<double> unit(0., 1.);
    const unsigned int                     p = kv.degree();
    const auto                             C = kv.extraction_operators();
    double                                 max_error = 0.;
    for (unsigned int e = 0; e < kv.n_spans(); ++e)
      for (unsigned int q = 0; q < 200; ++q)
        {
          const double t        = unit(rng);
          const auto   interval = kv.span_interval(e);
          const double u =
            interval.first + t * (interval.second - interval.first);
          std::vector<double> N(p + 1), B(p + 1);
          kv.basis_values(e, u, N.data());
          KnotVector::bernstein_values(p, t, B.data());
          for (unsigned int i = 0; i <= p; ++i)
            {
              double CB = 0.;
              for (unsigned int j = 0; j <= p; ++j)
                CB += C[e](i, j) * B[j];
              max_error = std::max(max_error, std::abs(CB - N[i]));
            }
        }
    return max_error;
  }
} // namespace

int
main()
{
  CHECK_TRUE(KnotVector::uniform(2, 4).extraction_operators().size() == 4);
  CHECK_CLOSE_ABS(max_extraction_error(KnotVector::uniform(2, 4)), 0., 1e-14);
  CHECK_CLOSE_ABS(max_extraction_error(KnotVector::uniform(1, 3)), 0., 1e-14);
  CHECK_CLOSE_ABS(max_extraction_error(
                    KnotVector({0, 0, 0, 0, 0.1, 0.4, 0.4, 0.7, 2, 2, 2, 2},
                               3)),
                  0.,
                  1e-14);
  CHECK_CLOSE_ABS(
    max_extraction_error(
      KnotVector({0, 0, 0, 0, 0, 0.2, 0.2, 0.5, 0.5, 0.5, 0.9, 1, 1, 1, 1, 1},
                 4)),
    0.,
    1e-14);
  CHECK_CLOSE_ABS(max_extraction_error(
                    KnotVector({0, 0, 0, 1, 3, 3, 4, 4, 4}, 2)),
                  0.,
                  1e-14);

  // Borden et al. 2011, uniform quadratic, 4 spans: first operator
  // [[1, 0, 0], [0, 1, 1/2], [0, 0, 1/2]].
  {
    const auto C = KnotVector::uniform(2, 4).extraction_operators();
    CHECK_CLOSE(C[0](0, 0), 1., 1e-15);
    CHECK_CLOSE(C[0](1, 2), 0.5, 1e-15);
    CHECK_CLOSE(C[0](2, 2), 0.5, 1e-15);
    CHECK_CLOSE(C[1](0, 0), 0.5, 1e-15);
    CHECK_CLOSE(C[1](1, 1), 1., 1e-15);
  }

  // Patch: element operators reproduce the tensor-product B-splines.
  {
    auto geometry = quarter_annulus(1., 2.);
    geometry.patch.elevate_degree(0, 1);
    geometry.patch.refine_uniformly(3);
    geometry.patch.insert_knots(1, {0.2});
    const auto                            &patch = geometry.patch;
    std::mt19937                           rng(3);
    std::uniform_real_distribution<double> unit(0., 1.);
    double                                 max_error = 0.;
    for (unsigned int e = 0; e < patch.n_elements(); ++e)
      {
        const auto C   = patch.element_extraction_operator(e);
        const auto box = patch.element_parameter_box(e);
        const auto m   = patch.element_multi_index(e);
        for (unsigned int q = 0; q < 20; ++q)
          {
            const double        t0 = unit(rng), t1 = unit(rng);
            const unsigned int  p0 = patch.degree(0), p1 = patch.degree(1);
            std::vector<double> N0(p0 + 1), N1(p1 + 1), B0(p0 + 1), B1(p1 + 1);
            patch.knot_vector(0).basis_values(
              m[0],
              box.first[0] + t0 * (box.second[0] - box.first[0]),
              N0.data());
            patch.knot_vector(1).basis_values(
              m[1],
              box.first[1] + t1 * (box.second[1] - box.first[1]),
              N1.data());
            KnotVector::bernstein_values(p0, t0, B0.data());
            KnotVector::bernstein_values(p1, t1, B1.data());
            for (unsigned int a = 0; a < C.m(); ++a)
              {
                double CB = 0.;
                for (unsigned int b = 0; b < C.n(); ++b)
                  CB += C(a, b) * B0[b % (p0 + 1)] * B1[b / (p0 + 1)];
                max_error =
                  std::max(max_error,
                           std::abs(CB - N0[a % (p0 + 1)] * N1[a / (p0 + 1)]));
              }
          }
      }
    CHECK_TRUE(patch.n_elements() == 3 * 4);
    CHECK_CLOSE_ABS(max_error, 0., 1e-14);
  }
  return isoimpact_tests::report();
}
