// Several NURBS patches glued C0 along conforming interfaces, with one
// global numbering of their control points (layer 1).
#ifndef isoimpact_nurbs_multipatch_h
#define isoimpact_nurbs_multipatch_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <isoimpact/nurbs/patch.h>

#include <memory>
#include <utility>
#include <vector>

namespace isoimpact
{
  namespace nurbs
  {
    /**
     * A set of patches of equal degrees. Control points on patch sides that
     * coincide (within `tolerance` times the diagonal of the bounding box
     * of all control points) and carry the same weight become one global
     * control point, so the basis is continuous across interfaces where the
     * sides are parametrised alike (same knots, same side control points).
     * Elements are numbered patch by patch; element_control_points() gives
     * global indices, element_rational_basis() the patch's functions in the
     * same local order. A side that shares some but not all of its control
     * points with other patches is a non-conforming interface and is
     * refused with an exception.
     */
    template <int dim>
    class MultiPatch
    {
    public:
      explicit MultiPatch(const std::vector<NURBSPatch<dim>> &patches,
                          const double tolerance = 1e-10);

      // One patch: global numbering = the patch's numbering.
      explicit MultiPatch(const NURBSPatch<dim> &patch);

      unsigned int
      n_patches() const
      {
        return patches.size();
      }

      const NURBSPatch<dim> &
      patch(const unsigned int p) const
      {
        return patches[p];
      }

      unsigned int
      degree(const unsigned int direction) const
      {
        return patches.front().degree(direction);
      }

      unsigned int
      n_functions_per_element() const
      {
        return patches.front().n_functions_per_element();
      }

      unsigned int
      n_elements() const
      {
        return element_offsets.back();
      }

      // (patch, element in the patch) of a global element.
      std::pair<unsigned int, unsigned int>
      local_element(const unsigned int element) const;

      unsigned int
      global_element(const unsigned int p,
                     const unsigned int patch_element) const
      {
        return element_offsets[p] + patch_element;
      }

      unsigned int
      n_control_points() const
      {
        return points.size();
      }

      const std::vector<dealii::Point<dim>> &
      control_points() const
      {
        return points;
      }

      const std::vector<double> &
      weights() const
      {
        return point_weights;
      }

      // Global index of control point `a` of patch `p`.
      unsigned int
      global_control_point(const unsigned int p, const unsigned int a) const
      {
        return global_indices[p][a];
      }

      void
      element_control_points(const unsigned int         element,
                             std::vector<unsigned int> &indices) const;

      void
      element_rational_basis(
        const unsigned int                   element,
        const dealii::Point<dim>            &reference_point,
        std::vector<double>                 &values,
        std::vector<dealii::Tensor<1, dim>> &gradients) const;

      // At several points (NURBSPatch::element_rational_basis).
      void
      element_rational_basis(
        const unsigned int                     element,
        const std::vector<dealii::Point<dim>> &reference_points,
        std::vector<double>                   &values,
        std::vector<dealii::Tensor<1, dim>>   &gradients) const;

    private:
      std::vector<NURBSPatch<dim>>           patches;
      std::vector<unsigned int>              element_offsets;
      std::vector<std::vector<unsigned int>> global_indices;
      std::vector<dealii::Point<dim>>        points;
      std::vector<double>                    point_weights;
    };

    // (patch, parametric direction)
    using KnotLine = std::pair<unsigned int, unsigned int>;

    /**
     * Local h-refinement of patches that are to be glued, keeping their
     * interfaces conforming. `links` ties pairs of (patch, direction) whose
     * knot vectors must stay equal (they meet along an interface, both
     * parametrised the same way); linked pairs form knot lines. In each of
     * `levels` passes, every span that carries an element with a corner
     * within `radius` of `center` is halved in all patches of its knot
     * line, so the refined zone is a union of tensor-product strips (no
     * hanging knots). Throws if linked knot vectors differ.
     */
    template <int dim>
    void
    refine_near_point(std::vector<NURBSPatch<dim>>                     &patches,
                      const std::vector<std::pair<KnotLine, KnotLine>> &links,
                      const dealii::Point<dim>                         &center,
                      const double                                      radius,
                      const unsigned int                                levels);

    // A one-patch MultiPatch of `patch`; throws if `patch` is null.
    template <int dim>
    std::shared_ptr<const MultiPatch<dim>>
    as_multipatch(const std::shared_ptr<const NURBSPatch<dim>> &patch);
  } // namespace nurbs
} // namespace isoimpact

#endif
