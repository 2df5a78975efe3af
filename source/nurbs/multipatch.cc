// Layer 1: patches glued along conforming interfaces.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/types.h>

#include <isoimpact/nurbs/knot_vector.h>
#include <isoimpact/nurbs/multipatch.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

using namespace dealii;

namespace isoimpact
{
  namespace nurbs
  {
    template <int dim>
    MultiPatch<dim>::MultiPatch(const std::vector<NURBSPatch<dim>> &patches,
                                const double                        tolerance)
      : patches(patches)
    {
      AssertThrow(!patches.empty(),
                  dealii::ExcMessage("MultiPatch: no patch given"));
      for (unsigned int p = 1; p < patches.size(); ++p)
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(patches[p].degree(d) == patches[0].degree(d),
                      dealii::ExcMessage(
                        "MultiPatch: patch " + std::to_string(p) +
                        " has degree " + std::to_string(patches[p].degree(d)) +
                        " in direction " + std::to_string(d) +
                        ", patch 0 has " +
                        std::to_string(patches[0].degree(d)) +
                        "; all patches must have the same degrees"));

      // The diagonal of the bounding box of all control points.
      element_offsets.push_back(0);
      dealii::Point<dim> lower = patches[0].control_points()[0], upper = lower;
      for (const auto &patch : patches)
        {
          element_offsets.push_back(element_offsets.back() +
                                    patch.n_elements());
          for (const auto &x : patch.control_points())
            for (unsigned int d = 0; d < dim; ++d)
              {
                lower[d] = std::min(lower[d], x[d]);
                upper[d] = std::max(upper[d], x[d]);
              }
        }
      const double distance_tolerance = tolerance * lower.distance(upper);

      // Side control points of earlier patches are the only candidates for
      // a match (quadratic search over boundary points, once in set-up).
      std::vector<unsigned int> candidates;
      global_indices.resize(patches.size());
      for (unsigned int p = 0; p < patches.size(); ++p)
        {
          const auto            &patch = patches[p];
          std::set<unsigned int> on_side;
          for (unsigned int f = 0; f < 2 * dim; ++f)
            for (const unsigned int a : patch.side_control_points(f))
              on_side.insert(a);
          global_indices[p].resize(patch.n_control_points());
          const std::size_t n_candidates_before = candidates.size();
          for (unsigned int a = 0; a < patch.n_control_points(); ++a)
            {
              const auto  &x     = patch.control_points()[a];
              const double w     = patch.weights()[a];
              unsigned int match = dealii::numbers::invalid_unsigned_int;
              if (on_side.count(a) != 0)
                for (std::size_t c = 0; c < n_candidates_before; ++c)
                  if (points[candidates[c]].distance(x) <= distance_tolerance)
                    {
                      match = candidates[c];
                      break;
                    }
              if (match != dealii::numbers::invalid_unsigned_int)
                {
                  AssertThrow(std::abs(point_weights[match] - w) <=
                                1e-10 * std::max(w, point_weights[match]),
                              dealii::ExcMessage(
                                "MultiPatch: patch " + std::to_string(p) +
                                " meets an earlier patch at control point (" +
                                to_string(x[0]) + ", " + to_string(x[1]) +
                                ") with weight " + to_string(w) + " against " +
                                to_string(point_weights[match]) +
                                "; glued control points need equal weights"));
                  global_indices[p][a] = match;
                }
              else
                {
                  global_indices[p][a] = points.size();
                  if (on_side.count(a) != 0)
                    candidates.push_back(points.size());
                  points.push_back(x);
                  point_weights.push_back(w);
                }
            }
        }

      // A side that shares two or more, but not all, of its control points
      // with another patch is glued only in part: non-conforming.
      for (unsigned int p = 0; p < patches.size(); ++p)
        for (unsigned int q = 0; q < patches.size(); ++q)
          if (q != p)
            {
              const std::set<unsigned int> of_q(global_indices[q].begin(),
                                                global_indices[q].end());
              for (unsigned int f = 0; f < 2 * dim; ++f)
                {
                  const auto   side   = patches[p].side_control_points(f);
                  unsigned int shared = 0;
                  for (const unsigned int a : side)
                    shared += of_q.count(global_indices[p][a]);
                  AssertThrow(
                    shared < 2 || shared == side.size(),
                    dealii::ExcMessage(
                      "MultiPatch: side " + std::to_string(f) + " of patch " +
                      std::to_string(p) + " shares " + std::to_string(shared) +
                      " of its " + std::to_string(side.size()) +
                      " control points with patch " + std::to_string(q) +
                      ": the interface is not conforming (refine "
                      "both patches alike)"));
                }
            }
    }



    template <int dim>
    MultiPatch<dim>::MultiPatch(const NURBSPatch<dim> &patch)
      : patches(1, patch)
      , element_offsets{0, patch.n_elements()}
      , global_indices(1)
      , points(patch.control_points())
      , point_weights(patch.weights())
    {
      global_indices[0].resize(patch.n_control_points());
      for (unsigned int a = 0; a < patch.n_control_points(); ++a)
        global_indices[0][a] = a;
    }



    template <int dim>
    std::pair<unsigned int, unsigned int>
    MultiPatch<dim>::local_element(const unsigned int element) const
    {
      AssertThrow(element < n_elements(),
                  dealii::ExcMessage("element " + std::to_string(element) +
                                     " is not an element of the patches (0 "
                                     "to " +
                                     std::to_string(n_elements()) + "-1)"));
      const unsigned int p = std::upper_bound(element_offsets.begin(),
                                              element_offsets.end(),
                                              element) -
                             element_offsets.begin() - 1;
      return {p, element - element_offsets[p]};
    }



    template <int dim>
    void
    MultiPatch<dim>::element_control_points(
      const unsigned int         element,
      std::vector<unsigned int> &indices) const
    {
      const auto [p, e] = local_element(element);
      patches[p].element_control_points(e, indices);
      for (auto &a : indices)
        a = global_indices[p][a];
    }



    template <int dim>
    void
    MultiPatch<dim>::element_rational_basis(
      const unsigned int                   element,
      const dealii::Point<dim>            &reference_point,
      std::vector<double>                 &values,
      std::vector<dealii::Tensor<1, dim>> &gradients) const
    {
      const auto [p, e] = local_element(element);
      patches[p].element_rational_basis(e, reference_point, values, gradients);
    }

    template <int dim>
    void
    MultiPatch<dim>::element_rational_basis(
      const unsigned int                     element,
      const std::vector<dealii::Point<dim>> &reference_points,
      std::vector<double>                   &values,
      std::vector<dealii::Tensor<1, dim>>   &gradients) const
    {
      const auto [p, e] = local_element(element);
      patches[p].element_rational_basis(e, reference_points, values, gradients);
    }

    template <int dim>
    std::shared_ptr<const MultiPatch<dim>>
    as_multipatch(const std::shared_ptr<const NURBSPatch<dim>> &patch)
    {
      AssertThrow(patch != nullptr, dealii::ExcMessage("no patch given"));
      return std::make_shared<const MultiPatch<dim>>(*patch);
    }

    template <int dim>
    void
    refine_near_point(std::vector<NURBSPatch<dim>>                     &patches,
                      const std::vector<std::pair<KnotLine, KnotLine>> &links,
                      const dealii::Point<dim>                         &center,
                      const double                                      radius,
                      const unsigned int                                levels)
    {
      // Knot lines: union-find over the (patch, direction) pairs.
      const unsigned int        n = patches.size() * dim;
      std::vector<unsigned int> parent(n);
      for (unsigned int i = 0; i < n; ++i)
        parent[i] = i;
      const auto find = [&](unsigned int i) {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]];
        return i;
      };
      for (const auto &link : links)
        parent[find(link.first.first * dim + link.first.second)] =
          find(link.second.first * dim + link.second.second);

      for (unsigned int level = 0; level < levels; ++level)
        {
          // Spans to halve, per knot line (its root), by span index.
          std::vector<std::set<unsigned int>> marked(n);
          for (unsigned int p = 0; p < patches.size(); ++p)
            for (unsigned int e = 0; e < patches[p].n_elements(); ++e)
              {
                const auto box   = patches[p].element_parameter_box(e);
                bool       close = false;
                for (unsigned int c = 0; c < (1u << dim) && !close; ++c)
                  {
                    dealii::Point<dim> corner;
                    for (unsigned int d = 0; d < dim; ++d)
                      corner[d] =
                        (c & (1u << d)) ? box.second[d] : box.first[d];
                    close =
                      patches[p].evaluate(corner).distance(center) < radius;
                  }
                if (close)
                  {
                    const auto index = patches[p].element_multi_index(e);
                    for (unsigned int d = 0; d < dim; ++d)
                      marked[find(p * dim + d)].insert(index[d]);
                  }
              }
          // Knots to insert, computed before any patch changes.
          std::vector<std::vector<double>> midpoints(n);
          for (unsigned int p = 0; p < patches.size(); ++p)
            for (unsigned int d = 0; d < dim; ++d)
              {
                const unsigned int root = find(p * dim + d);
                const unsigned int q = root / dim, r = root % dim;
                AssertThrow(patches[p].knot_vector(d).breakpoints() ==
                              patches[q].knot_vector(r).breakpoints(),
                            dealii::ExcMessage(
                              "refine_near_point: linked knot vectors of "
                              "patches " +
                              std::to_string(p) + " and " + std::to_string(q) +
                              " differ"));
                for (const unsigned int span : marked[root])
                  {
                    const auto interval =
                      patches[p].knot_vector(d).span_interval(span);
                    midpoints[p * dim + d].push_back(
                      0.5 * (interval.first + interval.second));
                  }
              }
          for (unsigned int p = 0; p < patches.size(); ++p)
            for (unsigned int d = 0; d < dim; ++d)
              if (!midpoints[p * dim + d].empty())
                patches[p].insert_knots(d, midpoints[p * dim + d]);
        }
    }

    template class MultiPatch<2>;
    template class MultiPatch<3>;
    template std::shared_ptr<const MultiPatch<2>>
    as_multipatch(const std::shared_ptr<const NURBSPatch<2>> &);
    template std::shared_ptr<const MultiPatch<3>>
    as_multipatch(const std::shared_ptr<const NURBSPatch<3>> &);
    template void
    refine_near_point(std::vector<NURBSPatch<2>> &,
                      const std::vector<std::pair<KnotLine, KnotLine>> &,
                      const dealii::Point<2> &,
                      const double,
                      const unsigned int);
  } // namespace nurbs
} // namespace isoimpact
