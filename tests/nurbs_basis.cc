// B-spline basis of KnotVector: partition of unity, non-negativity,
// derivatives against finite differences, hand-computed values.
#include <isoimpact/nurbs/knot_vector.h>

#include <algorithm>
#include <random>

#include "tests.h"

using namespace dealii;

using isoimpact::nurbs::KnotVector;

namespace
{
  // Values of all n basis functions at u (zero outside the span).
  std::vector<double>
  all_values(const KnotVector &kv, const double u)
  {
    std::vector<double> result(kv.n_basis_functions(), 0.), local;
    const unsigned int  span = kv.span_of(u);
    kv.basis_values(span, u, local);
    for (unsigned int i = 0; i <= kv.degree(); ++i)
      result[kv.first_basis_function(span) + i] = local[i];
    return result;
  }

  void
  check_knot_vector(const std::string &name, const KnotVector &kv)
  {
    std::mt19937                           rng(42);
    std::uniform_real_distribution<double> uniform(kv.front(), kv.back());
    const unsigned int                     p               = kv.degree();
    double                                 max_unity_error = 0., min_value = 1.;
    double                                 max_d1_error = 0., max_d2_error = 0.;
    for (unsigned int q = 0; q < 1000; ++q)
      {
        const double u   = uniform(rng);
        const auto   N   = all_values(kv, u);
        double       sum = 0.;
        for (const double v : N)
          {
            sum += v;
            min_value = std::min(min_value, v);
          }
        max_unity_error = std::max(max_unity_error, std::abs(sum - 1.));

        // Derivatives of the span's polynomial pieces against the fourth
        // order central difference (f(u-2h) - 8 f(u-h) + 8 f(u+h) -
        // f(u+2h)) / (12 h), exact for polynomials up to degree 4 apart
        // from round-off.
        const unsigned int  span = kv.span_of(u);
        const unsigned int  n    = 3;
        const unsigned int  size = (n + 1) * (p + 1);
        std::vector<double> d(size), dp1(size), dm1(size), dp2(size), dm2(size);
        const double        h = 1e-4 * (kv.back() - kv.front());
        kv.basis_derivatives(span, u, n, d.data());
        kv.basis_derivatives(span, u + h, n, dp1.data());
        kv.basis_derivatives(span, u - h, n, dm1.data());
        kv.basis_derivatives(span, u + 2 * h, n, dp2.data());
        kv.basis_derivatives(span, u - 2 * h, n, dm2.data());
        const auto fd = [&](const unsigned int k) {
          return (dm2[k] - 8 * dm1[k] + 8 * dp1[k] - dp2[k]) / (12 * h);
        };
        double scale1 = 1e-300, scale2 = 1e-300;
        for (unsigned int i = 0; i <= p; ++i)
          {
            scale1 = std::max(scale1, std::abs(d[(p + 1) + i]));
            scale2 = std::max(scale2, std::abs(d[2 * (p + 1) + i]));
          }
        for (unsigned int i = 0; i <= p; ++i)
          {
            // order 0 from basis_derivatives equals basis_values
            max_unity_error =
              std::max(max_unity_error,
                       std::abs(d[i] - N[kv.first_basis_function(span) + i]));
            max_d1_error =
              std::max(max_d1_error, std::abs(fd(i) - d[(p + 1) + i]) / scale1);
            if (p >= 2)
              max_d2_error =
                std::max(max_d2_error,
                         std::abs(fd((p + 1) + i) - d[2 * (p + 1) + i]) /
                           scale2);
            else // linear: second derivatives vanish
              max_d2_error =
                std::max(max_d2_error, std::abs(d[2 * (p + 1) + i]));
          }
      }
    std::cout << name << std::endl;
    CHECK_CLOSE_ABS(max_unity_error, 0., 1e-14);
    CHECK_TRUE(min_value >= 0.);
    CHECK_CLOSE_ABS(max_d1_error, 0., 1e-7);
    CHECK_CLOSE_ABS(max_d2_error, 0., 1e-7);
  }
} // namespace

int
main()
{
  check_knot_vector("uniform p=2, 5 spans", KnotVector::uniform(2, 5));
  check_knot_vector("p=3 non-uniform, repeated knot",
                    KnotVector({0, 0, 0, 0, 0.1, 0.4, 0.4, 0.7, 2, 2, 2, 2},
                               3));
  check_knot_vector(
    "p=4 on [-1, 3]",
    KnotVector({-1, -1, -1, -1, -1, 0, 0.5, 0.5, 0.5, 3, 3, 3, 3, 3}, 4));
  check_knot_vector("p=1", KnotVector({0, 0, 0.3, 0.5, 1, 1}, 1));

  // Hand computation, p = 2, U = {0,0,0,1,3,3,4,4,4} (indices 0..8),
  // n = 6 functions N_0..N_5, spans [0,1], [1,3], [3,4], knot 3 repeated.
  // u = 2: knot span k = 3 (U_3 = 1 <= 2 < U_4 = 3), non-zero N_1, N_2, N_3.
  //   degree 1: N_{2,1} = (U_4 - u)/(U_4 - U_3) = 1/2,
  //             N_{3,1} = (u - U_3)/(U_4 - U_3) = 1/2;
  //   degree 2: N_1 = (U_4 - u)/(U_4 - U_2) N_{2,1} = (1/3)(1/2) = 1/6,
  //             N_2 = (u - U_2)/(U_4 - U_2) N_{2,1}
  //                   + (U_5 - u)/(U_5 - U_3) N_{3,1} = 1/3 + 1/4 = 7/12,
  //             N_3 = (u - U_3)/(U_5 - U_3) N_{3,1} = (1/2)(1/2) = 1/4.
  // u = 3.5: k = 5 (U_5 = 3 <= 3.5 < U_6 = 4), non-zero N_3, N_4, N_5.
  //   degree 1: N_{4,1} = (U_6 - u)/(U_6 - U_5) = 1/2, N_{5,1} = 1/2;
  //   degree 2: N_3 = (U_6 - u)/(U_6 - U_4) N_{4,1} = (1/2)(1/2) = 1/4,
  //             N_4 = (u - U_4)/(U_6 - U_4) N_{4,1}
  //                   + (U_7 - u)/(U_7 - U_5) N_{5,1} = 1/4 + 1/4 = 1/2,
  //             N_5 = (u - U_5)/(U_7 - U_5) N_{5,1} = 1/4.
  // u = 3 (double knot, C^0): N_3 = (U_6 - 3)/(U_6 - U_4) * 1 = 1, rest 0.
  // First derivative at u = 2 (A2.3 formula N'_{i,2} = 2 N_{i,1}/(U_{i+2} -
  // U_i) - 2 N_{i+1,1}/(U_{i+3} - U_{i+1})): N'_1 = 0 - 2 (1/2)/(3 - 0) =
  // -1/3, N'_2 = 2 (1/2)/3 - 2 (1/2)/(3 - 1) = 1/3 - 1/2 = -1/6,
  // N'_3 = 2 (1/2)/2 - 0 = 1/2.
  {
    const KnotVector kv({0, 0, 0, 1, 3, 3, 4, 4, 4}, 2);
    CHECK_TRUE(kv.n_basis_functions() == 6);
    CHECK_TRUE(kv.n_spans() == 3);
    CHECK_TRUE(kv.multiplicity(3.) == 2);
    CHECK_TRUE(kv.span_of(2.) == 1 && kv.first_basis_function(1) == 1);
    CHECK_TRUE(kv.span_of(4.) == 2 && kv.span_of(3.) == 2);
    const auto N2 = all_values(kv, 2.);
    CHECK_CLOSE_ABS(N2[0], 0., 1e-16);
    CHECK_CLOSE(N2[1], 1. / 6., 1e-15);
    CHECK_CLOSE(N2[2], 7. / 12., 1e-15);
    CHECK_CLOSE(N2[3], 1. / 4., 1e-15);
    const auto N35 = all_values(kv, 3.5);
    CHECK_CLOSE(N35[3], 0.25, 1e-15);
    CHECK_CLOSE(N35[4], 0.5, 1e-15);
    CHECK_CLOSE(N35[5], 0.25, 1e-15);
    const auto N3 = all_values(kv, 3.);
    CHECK_CLOSE(N3[3], 1., 1e-15);
    CHECK_CLOSE_ABS(N3[4] + N3[5], 0., 1e-16);
    dealii::FullMatrix<double> ders;
    kv.basis_derivatives(1, 2., 2, ders);
    CHECK_CLOSE(ders(1, 0), -1. / 3., 1e-14);
    CHECK_CLOSE(ders(1, 1), -1. / 6., 1e-14);
    CHECK_CLOSE(ders(1, 2), 1. / 2., 1e-14);
    const auto breakpoints = kv.breakpoints();
    CHECK_TRUE(breakpoints == std::vector<double>({0, 1, 3, 4}));
  }
  return isoimpact_tests::report();
}
