// Refinement leaves the geometry unchanged: knot insertion, uniform, graded,
// degree elevation and k-refinement of the half disk; refinement matrices of
// KnotVector reproduce the old basis.
#include <isoimpact/nurbs/geometries.h>

#include <random>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;
using dealii::Point;

namespace
{
  std::vector<Point<2>>
  random_parameters()
  {
    std::mt19937                           rng(11);
    std::uniform_real_distribution<double> unit(0., 1.);
    std::vector<Point<2>>                  result;
    for (unsigned int i = 0; i < 500; ++i)
      result.emplace_back(unit(rng), unit(rng));
    // corners and sides too
    result.emplace_back(0., 0.);
    result.emplace_back(1., 1.);
    result.emplace_back(0., 0.5);
    result.emplace_back(0.5, 1.);
    return result;
  }

  // max |X_new - X_old| / size over the sample parameters.
  double
  geometry_change(const NURBSPatch<2>         &before,
                  const NURBSPatch<2>         &after,
                  const std::vector<Point<2>> &parameters,
                  const double                 size)
  {
    double max_change = 0.;
    for (const auto &xi : parameters)
      max_change =
        std::max(max_change,
                 before.evaluate(xi).distance(after.evaluate(xi)) / size);
    return max_change;
  }

  // max_u |N_old_i(u) - sum_j T(j,i) N_new_j(u)|.
  double
  refinement_matrix_error(const KnotVector             &old_kv,
                          const KnotVector::Refinement &refinement)
  {
    const KnotVector &new_kv    = refinement.knot_vector;
    double            max_error = 0.;
    for (unsigned int q = 0; q <= 400; ++q)
      {
        const double u =
          old_kv.front() + (old_kv.back() - old_kv.front()) * q / 400.;
        std::vector<double> old_values(old_kv.n_basis_functions(), 0.);
        std::vector<double> new_values(new_kv.n_basis_functions(), 0.), local;
        unsigned int        span = old_kv.span_of(u);
        old_kv.basis_values(span, u, local);
        for (unsigned int i = 0; i < local.size(); ++i)
          old_values[old_kv.first_basis_function(span) + i] = local[i];
        span = new_kv.span_of(u);
        new_kv.basis_values(span, u, local);
        for (unsigned int i = 0; i < local.size(); ++i)
          new_values[new_kv.first_basis_function(span) + i] = local[i];
        for (unsigned int i = 0; i < old_values.size(); ++i)
          {
            double sum = 0.;
            for (unsigned int j = 0; j < new_values.size(); ++j)
              sum += refinement.matrix(j, i) * new_values[j];
            max_error = std::max(max_error, std::abs(sum - old_values[i]));
          }
      }
    return max_error;
  }
} // namespace

int
main()
{
  const double   R = 1.3;
  const Point<2> c(-0.2, 0.4);
  const auto     parameters = random_parameters();
  const auto     original   = half_disk(R, c).patch;

  {
    auto patch = original;
    patch.insert_knots(0, {0.3, 0.3, 0.71});
    patch.insert_knots(1, {0.5});
    CHECK_TRUE(patch.knot_vector(0).n_knots() == 9 &&
               patch.knot_vector(0).multiplicity(0.3) == 2);
    CHECK_TRUE(patch.n_elements() == 3 * 2);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
  }
  {
    auto patch = original;
    patch.refine_uniformly(5);
    patch.refine_uniformly(1, 2);
    CHECK_TRUE(patch.n_elements() == 5 * 10);
    CHECK_CLOSE(patch.knot_vector(1).span_interval(3).second, 0.4, 1e-15);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
  }
  {
    auto patch = original;
    patch.elevate_degree(0, 1);
    patch.elevate_degree(1, 2);
    CHECK_TRUE(patch.degree(0) == 3 && patch.degree(1) == 4);
    CHECK_TRUE(patch.n_control_points() == 4 * 5);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
    // elevation of an already refined patch (interior knots, C^1 and C^0)
    auto refined = original;
    refined.insert_knots(0, {0.25, 0.6, 0.6});
    refined.refine_uniformly(1, 3);
    auto elevated = refined;
    elevated.elevate_degree(0, 2);
    elevated.elevate_degree(1, 1);
    CHECK_TRUE(elevated.knot_vector(0).multiplicity(0.6) == 4 &&
               elevated.knot_vector(0).multiplicity(0.25) == 3);
    CHECK_CLOSE_ABS(geometry_change(original, elevated, parameters, R),
                    0.,
                    1e-13);
  }
  {
    auto patch = original;
    patch.k_refine(1, 4);
    CHECK_TRUE(patch.degree(0) == 3 && patch.n_elements() == 16);
    // maximal continuity: interior knots simple
    CHECK_TRUE(patch.knot_vector(0).multiplicity(0.25) == 1);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
    patch.k_refine(0, 1, 2);
    CHECK_TRUE(patch.degree(0) == 4 && patch.n_elements() == 32);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
  }
  {
    auto patch = original;
    patch.refine_uniformly(2);
    patch.refine_graded(0, 0, 4, 2.);
    patch.refine_graded(1, 1, 2, 1.5);
    // span next to xi_0 = 0: first span 0.5 split as h, 2h, 4h, 8h, 16h
    CHECK_CLOSE(patch.knot_vector(0).span_interval(0).second, 0.5 / 31., 1e-14);
    CHECK_CLOSE(patch.knot_vector(0).span_interval(1).second, 1.5 / 31., 1e-14);
    CHECK_TRUE(patch.n_elements() == 6 * 4);
    CHECK_CLOSE_ABS(geometry_change(original, patch, parameters, R), 0., 1e-13);
  }

  // Refinement matrices of KnotVector.
  {
    const KnotVector kv({0, 0, 0, 0, 0.3, 0.5, 0.5, 1, 1, 1, 1}, 3);
    CHECK_CLOSE_ABS(refinement_matrix_error(kv, kv.insert_knot(0.4, 2)),
                    0.,
                    1e-14);
    CHECK_CLOSE_ABS(refinement_matrix_error(kv, kv.insert_knot(0.5)),
                    0.,
                    1e-14);
    CHECK_CLOSE_ABS(refinement_matrix_error(kv,
                                            kv.insert_knots({0.9, 0.1, 0.1})),
                    0.,
                    1e-14);
    CHECK_CLOSE_ABS(refinement_matrix_error(kv, kv.elevate_degree(1)),
                    0.,
                    1e-14);
    CHECK_CLOSE_ABS(refinement_matrix_error(kv, kv.elevate_degree(3)),
                    0.,
                    1e-13);
    // rows of the insertion matrix sum to 1 (partition of unity)
    const auto refinement    = kv.insert_knot(0.7, 3);
    double     max_row_error = 0.;
    for (unsigned int j = 0; j < refinement.matrix.m(); ++j)
      {
        double sum = 0.;
        for (unsigned int i = 0; i < refinement.matrix.n(); ++i)
          sum += refinement.matrix(j, i);
        max_row_error = std::max(max_row_error, std::abs(sum - 1.));
      }
    CHECK_CLOSE_ABS(max_row_error, 0., 1e-15);
  }
  return isoimpact_tests::report();
}
