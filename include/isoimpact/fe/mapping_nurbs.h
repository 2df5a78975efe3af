// Layer 2: the exact rational geometry of a NURBS patch as a deal.II Mapping.
#ifndef isoimpact_mapping_nurbs_h
#define isoimpact_mapping_nurbs_h

#include <deal.II/base/derivative_form.h>
#include <deal.II/base/tensor.h>

#include <deal.II/fe/mapping.h>

#include <isoimpact/nurbs/multipatch.h>
#include <isoimpact/nurbs/patch.h>

#include <memory>
#include <vector>

namespace isoimpact
{

  /**
   * The map of a NURBS patch, cell by cell: the triangulation has one cell
   * per knot span (element) of the patch, and cell->user_index() is the
   * element index. The unit cell [0,1]^dim is the element's reference cell
   * (see NURBSPatch::element_rational_basis), so
   *   x(xhat) = sum_a R_a(xhat) P_a,  J = sum_a P_a (grad_xhat R_a)^T.
   * The cell's vertices must be the images of the unit cell's vertices
   * (preserves_vertex_locations() is true).
   *
   * Two knot spans with the same corners can have different weights:
   * fill_fe_values() returns CellSimilarity::invalid_next_cell, so FEValues
   * never reuses data of a previous cell.
   *
   * Implemented transforms: for vectors mapping_contravariant,
   * mapping_covariant, mapping_piola; for rank-2 tensors and derivative forms
   * mapping_contravariant, mapping_covariant, mapping_covariant_gradient,
   * mapping_contravariant_gradient. Subfaces (hanging nodes) do not occur in
   * a patch mesh and are not implemented. Only dim = spacedim.
   */
  template <int dim>
  class MappingNURBS : public dealii::Mapping<dim>
  {
  public:
    explicit MappingNURBS(
      const std::shared_ptr<const nurbs::MultiPatch<dim>> &patches);

    // One patch.
    explicit MappingNURBS(
      const std::shared_ptr<const nurbs::NURBSPatch<dim>> &patch);

    const nurbs::MultiPatch<dim> &
    patches() const
    {
      return *shared_patches;
    }

    std::unique_ptr<dealii::Mapping<dim>>
    clone() const override;

    boost::container::small_vector<dealii::Point<dim>,
                                   dealii::GeometryInfo<dim>::vertices_per_cell>
    get_vertices(const typename dealii::Triangulation<dim>::cell_iterator &cell)
      const override;

    bool
    preserves_vertex_locations() const override
    {
      return true;
    }

    bool
    is_compatible_with(
      const dealii::ReferenceCell &reference_cell) const override;

    dealii::Point<dim>
    transform_unit_to_real_cell(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const dealii::Point<dim> &p) const override;

    // Newton's method; throws Mapping::ExcTransformationFailed if it does not
    // converge (e.g. far outside the cell or at a degenerate point).
    dealii::Point<dim>
    transform_real_to_unit_cell(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const dealii::Point<dim> &p) const override;

    void
    transform(
      const dealii::ArrayView<const dealii::Tensor<1, dim>> &input,
      const dealii::MappingKind                              kind,
      const typename dealii::Mapping<dim>::InternalDataBase &internal,
      const dealii::ArrayView<dealii::Tensor<1, dim>> &output) const override;

    void
    transform(
      const dealii::ArrayView<const dealii::DerivativeForm<1, dim, dim>> &input,
      const dealii::MappingKind                                           kind,
      const typename dealii::Mapping<dim>::InternalDataBase &internal,
      const dealii::ArrayView<dealii::Tensor<2, dim>> &output) const override;

    void
    transform(
      const dealii::ArrayView<const dealii::Tensor<2, dim>> &input,
      const dealii::MappingKind                              kind,
      const typename dealii::Mapping<dim>::InternalDataBase &internal,
      const dealii::ArrayView<dealii::Tensor<2, dim>> &output) const override;

    void
    transform(
      const dealii::ArrayView<const dealii::DerivativeForm<2, dim, dim>> &input,
      const dealii::MappingKind                                           kind,
      const typename dealii::Mapping<dim>::InternalDataBase &internal,
      const dealii::ArrayView<dealii::Tensor<3, dim>> &output) const override;

    void
    transform(
      const dealii::ArrayView<const dealii::Tensor<3, dim>> &input,
      const dealii::MappingKind                              kind,
      const typename dealii::Mapping<dim>::InternalDataBase &internal,
      const dealii::ArrayView<dealii::Tensor<3, dim>> &output) const override;

    // Per-quadrature-point data of the present cell or face.
    class InternalData : public dealii::Mapping<dim>::InternalDataBase
    {
    public:
      void
      resize(const unsigned int n_points) const;

      std::size_t
      memory_consumption() const override;

      // J, J^{-T}, det J at the quadrature points.
      mutable std::vector<dealii::Tensor<2, dim>> jacobians;
      mutable std::vector<dealii::Tensor<2, dim>> covariant;
      mutable std::vector<double>                 determinants;
      // Scratch for the basis of an element.
      mutable std::vector<double>                 values;
      mutable std::vector<dealii::Tensor<1, dim>> gradients;
      mutable std::vector<unsigned int>           control_points;
    };

  protected:
    dealii::UpdateFlags
    requires_update_flags(
      const dealii::UpdateFlags update_flags) const override;

    std::unique_ptr<typename dealii::Mapping<dim>::InternalDataBase>
    get_data(const dealii::UpdateFlags      update_flags,
             const dealii::Quadrature<dim> &quadrature) const override;

    using dealii::Mapping<dim>::get_face_data;

    std::unique_ptr<typename dealii::Mapping<dim>::InternalDataBase>
    get_face_data(
      const dealii::UpdateFlags               update_flags,
      const dealii::hp::QCollection<dim - 1> &quadrature) const override;

    std::unique_ptr<typename dealii::Mapping<dim>::InternalDataBase>
    get_subface_data(
      const dealii::UpdateFlags          update_flags,
      const dealii::Quadrature<dim - 1> &quadrature) const override;

    dealii::CellSimilarity::Similarity
    fill_fe_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const dealii::CellSimilarity::Similarity                  cell_similarity,
      const dealii::Quadrature<dim>                            &quadrature,
      const typename dealii::Mapping<dim>::InternalDataBase    &internal_data,
      dealii::internal::FEValuesImplementation::MappingRelatedData<dim, dim>
        &output_data) const override;

    using dealii::Mapping<dim>::fill_fe_face_values;

    void
    fill_fe_face_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const unsigned int                                        face_no,
      const dealii::hp::QCollection<dim - 1>                   &quadrature,
      const typename dealii::Mapping<dim>::InternalDataBase    &internal_data,
      dealii::internal::FEValuesImplementation::MappingRelatedData<dim, dim>
        &output_data) const override;

    void
    fill_fe_subface_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const unsigned int                                        face_no,
      const unsigned int                                        subface_no,
      const dealii::Quadrature<dim - 1>                        &quadrature,
      const typename dealii::Mapping<dim>::InternalDataBase    &internal_data,
      dealii::internal::FEValuesImplementation::MappingRelatedData<dim, dim>
        &output_data) const override;

  private:
    // x and J at a point of the unit cell of `element`, using the scratch of
    // `data`.
    void
    evaluate(const unsigned int        element,
             const dealii::Point<dim> &unit_point,
             const InternalData       &data,
             dealii::Point<dim>       &x,
             dealii::Tensor<2, dim>   &jacobian) const;

    // Fills the mapping data at the given points of the unit cell of the
    // cell (cell quadrature or face quadrature projected into the cell).
    void
    compute_at_points(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const std::vector<dealii::Point<dim>>                    &points,
      const InternalData                                       &data,
      dealii::internal::FEValuesImplementation::MappingRelatedData<dim, dim>
        &output_data) const;

    std::shared_ptr<const nurbs::MultiPatch<dim>> shared_patches;
  };
} // namespace isoimpact

#endif
