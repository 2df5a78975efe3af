// Layer 2: the rational B-spline (NURBS) basis of a patch as a deal.II
// FiniteElement in a "broken" layout.
#ifndef isoimpact_fe_nurbs_h
#define isoimpact_fe_nurbs_h

#include <deal.II/base/tensor.h>

#include <deal.II/fe/fe.h>

#include <isoimpact/nurbs/multipatch.h>
#include <isoimpact/nurbs/patch.h>

#include <memory>
#include <string>
#include <vector>

namespace isoimpact
{

  /**
   * Scalar NURBS element of a patch. On the cell of knot span e
   * (cell->user_index() == e) its (p_0+1)...(p_{dim-1}+1) shape functions
   * are the rational functions R_a non-zero on e, in the local order of
   * NURBSPatch::element_control_points(e). For the DoFHandler all of them
   * sit in the cell interior (like FE_DGQ): a DoFHandler numbers them
   * per cell ("broken"), and the true spline numbering (control points) is
   * kept by the user (see DiscretizationIGA). FESystem, FEValues,
   * FEFaceValues and DataOut work unchanged, with any mapping whose unit
   * cell is the knot span's reference cell, in practice MappingNURBS.
   *
   * The shape functions depend on the cell, so shape_value() and friends
   * throw ExcUnitShapeValuesDoNotExist; values and gradients are computed
   * in fill_fe_values() (gradients are pushed forward with the mapping's
   * covariant transform). Second derivatives and subfaces are not
   * implemented.
   *
   * Note: FEValues skips recomputing data on cells it considers
   * translations of the previous one; MappingNURBS forbids that, other
   * mappings (e.g. MappingQ, MappingCartesian) do not, so use this element
   * with MappingNURBS.
   */
  template <int dim>
  class FE_NURBS : public dealii::FiniteElement<dim>
  {
  public:
    explicit FE_NURBS(
      const std::shared_ptr<const nurbs::MultiPatch<dim>> &patches);

    // One patch.
    explicit FE_NURBS(
      const std::shared_ptr<const nurbs::NURBSPatch<dim>> &patch);

    const nurbs::MultiPatch<dim> &
    patches() const
    {
      return *shared_patches;
    }

    std::string
    get_name() const override;

    std::unique_ptr<dealii::FiniteElement<dim>>
    clone() const override;

    dealii::UpdateFlags
    requires_update_flags(
      const dealii::UpdateFlags update_flags) const override;

    double
    shape_value(const unsigned int        i,
                const dealii::Point<dim> &p) const override;

    double
    shape_value_component(const unsigned int        i,
                          const dealii::Point<dim> &p,
                          const unsigned int        component) const override;

    dealii::Tensor<1, dim>
    shape_grad(const unsigned int        i,
               const dealii::Point<dim> &p) const override;

    dealii::Tensor<1, dim>
    shape_grad_component(const unsigned int        i,
                         const dealii::Point<dim> &p,
                         const unsigned int        component) const override;

    std::size_t
    memory_consumption() const override;

    class InternalData : public dealii::FiniteElement<dim>::InternalDataBase
    {
    public:
      mutable std::vector<double>                 values;
      mutable std::vector<dealii::Tensor<1, dim>> gradients;
      // Unit-cell gradients of all shape functions at all points, row i.
      mutable dealii::Table<2, dealii::Tensor<1, dim>> unit_gradients;
    };

  protected:
    std::unique_ptr<typename dealii::FiniteElement<dim>::InternalDataBase>
    get_data(const dealii::UpdateFlags      update_flags,
             const dealii::Mapping<dim>    &mapping,
             const dealii::Quadrature<dim> &quadrature,
             dealii::internal::FEValuesImplementation::
               FiniteElementRelatedData<dim, dim> &output_data) const override;

    void
    fill_fe_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const dealii::CellSimilarity::Similarity                  cell_similarity,
      const dealii::Quadrature<dim>                            &quadrature,
      const dealii::Mapping<dim>                               &mapping,
      const typename dealii::Mapping<dim>::InternalDataBase &mapping_internal,
      const dealii::internal::FEValuesImplementation::MappingRelatedData<dim,
                                                                         dim>
                                                                  &mapping_data,
      const typename dealii::FiniteElement<dim>::InternalDataBase &fe_internal,
      dealii::internal::FEValuesImplementation::FiniteElementRelatedData<dim,
                                                                         dim>
        &output_data) const override;

    using dealii::FiniteElement<dim>::fill_fe_face_values;

    void
    fill_fe_face_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const unsigned int                                        face_no,
      const dealii::hp::QCollection<dim - 1>                   &quadrature,
      const dealii::Mapping<dim>                               &mapping,
      const typename dealii::Mapping<dim>::InternalDataBase &mapping_internal,
      const dealii::internal::FEValuesImplementation::MappingRelatedData<dim,
                                                                         dim>
                                                                  &mapping_data,
      const typename dealii::FiniteElement<dim>::InternalDataBase &fe_internal,
      dealii::internal::FEValuesImplementation::FiniteElementRelatedData<dim,
                                                                         dim>
        &output_data) const override;

    void
    fill_fe_subface_values(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const unsigned int                                        face_no,
      const unsigned int                                        sub_no,
      const dealii::Quadrature<dim - 1>                        &quadrature,
      const dealii::Mapping<dim>                               &mapping,
      const typename dealii::Mapping<dim>::InternalDataBase &mapping_internal,
      const dealii::internal::FEValuesImplementation::MappingRelatedData<dim,
                                                                         dim>
                                                                  &mapping_data,
      const typename dealii::FiniteElement<dim>::InternalDataBase &fe_internal,
      dealii::internal::FEValuesImplementation::FiniteElementRelatedData<dim,
                                                                         dim>
        &output_data) const override;

  private:
    // Values and gradients at the given points of the cell's unit cell.
    void
    compute_at_points(
      const typename dealii::Triangulation<dim>::cell_iterator &cell,
      const std::vector<dealii::Point<dim>>                    &points,
      const dealii::Mapping<dim>                               &mapping,
      const typename dealii::Mapping<dim>::InternalDataBase &mapping_internal,
      const InternalData                                    &data,
      dealii::internal::FEValuesImplementation::FiniteElementRelatedData<dim,
                                                                         dim>
        &output_data) const;

    std::shared_ptr<const nurbs::MultiPatch<dim>> shared_patches;
  };
} // namespace isoimpact

#endif
