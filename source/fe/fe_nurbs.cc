// Layer 2: NURBS shape functions of a patch as a broken deal.II element.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/memory_consumption.h>
#include <deal.II/base/qprojector.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria.h>

#include <isoimpact/fe/fe_nurbs.h>

#include <algorithm>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    template <int dim>
    FiniteElementData<dim>
    make_fe_data(const nurbs::MultiPatch<dim> &patches)
    {
      std::vector<unsigned int> dofs_per_object(dim + 1, 0);
      dofs_per_object[dim] = patches.n_functions_per_element();
      unsigned int degree  = 0;
      for (unsigned int d = 0; d < dim; ++d)
        degree = std::max(degree, patches.degree(d));
      return FiniteElementData<dim>(dofs_per_object,
                                    1,
                                    degree,
                                    FiniteElementData<dim>::L2);
    }

    template <int dim>
    const nurbs::MultiPatch<dim> &
    checked(const std::shared_ptr<const nurbs::MultiPatch<dim>> &patches)
    {
      AssertThrow(patches != nullptr, ExcMessage("FE_NURBS: no patch given"));
      return *patches;
    }
  } // namespace



  template <int dim>
  FE_NURBS<dim>::FE_NURBS(
    const std::shared_ptr<const nurbs::NURBSPatch<dim>> &patch)
    : FE_NURBS(nurbs::as_multipatch(patch))
  {}



  template <int dim>
  FE_NURBS<dim>::FE_NURBS(
    const std::shared_ptr<const nurbs::MultiPatch<dim>> &patches)
    : FiniteElement<dim>(
        make_fe_data(checked(patches)),
        std::vector<bool>(patches->n_functions_per_element(), true),
        std::vector<ComponentMask>(patches->n_functions_per_element(),
                                   ComponentMask(1, true)))
    , shared_patches(patches)
  {}



  template <int dim>
  std::string
  FE_NURBS<dim>::get_name() const
  {
    std::string name = "FE_NURBS<" + std::to_string(dim) + ">(";
    for (unsigned int d = 0; d < dim; ++d)
      name += (d > 0 ? "," : "") + std::to_string(shared_patches->degree(d));
    return name + ")";
  }



  template <int dim>
  std::unique_ptr<FiniteElement<dim>>
  FE_NURBS<dim>::clone() const
  {
    return std::make_unique<FE_NURBS<dim>>(*this);
  }



  template <int dim>
  UpdateFlags
  FE_NURBS<dim>::requires_update_flags(const UpdateFlags flags) const
  {
    UpdateFlags out = flags & update_values;
    if (flags & update_gradients)
      out |= update_gradients | update_covariant_transformation;
    AssertThrow(!(flags & (update_hessians | update_3rd_derivatives)),
                ExcMessage("FE_NURBS: second and third derivatives are not "
                           "implemented"));
    return out;
  }



  template <int dim>
  double
  FE_NURBS<dim>::shape_value(const unsigned int, const Point<dim> &) const
  {
    AssertThrow(false,
                (typename FiniteElement<dim>::ExcUnitShapeValuesDoNotExist()));
    return 0.;
  }

  template <int dim>
  double
  FE_NURBS<dim>::shape_value_component(const unsigned int,
                                       const Point<dim> &,
                                       const unsigned int) const
  {
    AssertThrow(false,
                (typename FiniteElement<dim>::ExcUnitShapeValuesDoNotExist()));
    return 0.;
  }

  template <int dim>
  Tensor<1, dim>
  FE_NURBS<dim>::shape_grad(const unsigned int, const Point<dim> &) const
  {
    AssertThrow(false,
                (typename FiniteElement<dim>::ExcUnitShapeValuesDoNotExist()));
    return {};
  }

  template <int dim>
  Tensor<1, dim>
  FE_NURBS<dim>::shape_grad_component(const unsigned int,
                                      const Point<dim> &,
                                      const unsigned int) const
  {
    AssertThrow(false,
                (typename FiniteElement<dim>::ExcUnitShapeValuesDoNotExist()));
    return {};
  }



  template <int dim>
  std::size_t
  FE_NURBS<dim>::memory_consumption() const
  {
    return sizeof(*this);
  }



  template <int dim>
  std::unique_ptr<typename FiniteElement<dim>::InternalDataBase>
  FE_NURBS<dim>::get_data(
    const UpdateFlags update_flags,
    const Mapping<dim> &,
    const Quadrature<dim> &,
    internal::FEValuesImplementation::FiniteElementRelatedData<dim, dim> &)
    const
  {
    auto data         = std::make_unique<InternalData>();
    data->update_each = requires_update_flags(update_flags);
    return data;
  }



  template <int dim>
  void
  FE_NURBS<dim>::compute_at_points(
    const typename Triangulation<dim>::cell_iterator &cell,
    const std::vector<Point<dim>>                    &points,
    const Mapping<dim>                               &mapping,
    const typename Mapping<dim>::InternalDataBase    &mapping_internal,
    const InternalData                               &data,
    internal::FEValuesImplementation::FiniteElementRelatedData<dim, dim>
      &output_data) const
  {
    const unsigned int element = cell->user_index();
    AssertThrow(element < shared_patches->n_elements(),
                ExcMessage(
                  "FE_NURBS: the cell's user_index " + std::to_string(element) +
                  " is not an element of the patches (0 to " +
                  std::to_string(shared_patches->n_elements()) + "-1)"));
    const UpdateFlags  flags    = data.update_each;
    const unsigned int n_points = points.size();
    const unsigned int n_shape  = this->n_dofs_per_cell();
    if ((flags & update_gradients) && (data.unit_gradients.size(0) != n_shape ||
                                       data.unit_gradients.size(1) != n_points))
      data.unit_gradients.reinit(n_shape, n_points);

    shared_patches->element_rational_basis(element,
                                           points,
                                           data.values,
                                           data.gradients);
    for (unsigned int q = 0; q < n_points; ++q)
      {
        if (flags & update_values)
          for (unsigned int i = 0; i < n_shape; ++i)
            output_data.shape_values(i, q) = data.values[q * n_shape + i];
        if (flags & update_gradients)
          for (unsigned int i = 0; i < n_shape; ++i)
            data.unit_gradients(i, q) = data.gradients[q * n_shape + i];
      }

    if (flags & update_gradients)
      for (unsigned int i = 0; i < n_shape; ++i)
        mapping.transform(
          ArrayView<const Tensor<1, dim>>(&data.unit_gradients(i, 0), n_points),
          mapping_covariant,
          mapping_internal,
          ArrayView<Tensor<1, dim>>(&output_data.shape_gradients(i, 0),
                                    n_points));
  }



  template <int dim>
  void
  FE_NURBS<dim>::fill_fe_values(
    const typename Triangulation<dim>::cell_iterator &cell,
    const CellSimilarity::Similarity,
    const Quadrature<dim>                         &quadrature,
    const Mapping<dim>                            &mapping,
    const typename Mapping<dim>::InternalDataBase &mapping_internal,
    const internal::FEValuesImplementation::MappingRelatedData<dim, dim> &,
    const typename FiniteElement<dim>::InternalDataBase &fe_internal,
    internal::FEValuesImplementation::FiniteElementRelatedData<dim, dim>
      &output_data) const
  {
    Assert(dynamic_cast<const InternalData *>(&fe_internal) != nullptr,
           ExcInternalError());
    // The functions depend on the cell: always recompute, whatever the
    // similarity to the previous cell.
    compute_at_points(cell,
                      quadrature.get_points(),
                      mapping,
                      mapping_internal,
                      static_cast<const InternalData &>(fe_internal),
                      output_data);
  }



  template <int dim>
  void
  FE_NURBS<dim>::fill_fe_face_values(
    const typename Triangulation<dim>::cell_iterator &cell,
    const unsigned int                                face_no,
    const hp::QCollection<dim - 1>                   &quadrature,
    const Mapping<dim>                               &mapping,
    const typename Mapping<dim>::InternalDataBase    &mapping_internal,
    const internal::FEValuesImplementation::MappingRelatedData<dim, dim> &,
    const typename FiniteElement<dim>::InternalDataBase &fe_internal,
    internal::FEValuesImplementation::FiniteElementRelatedData<dim, dim>
      &output_data) const
  {
    Assert(dynamic_cast<const InternalData *>(&fe_internal) != nullptr,
           ExcInternalError());
    AssertDimension(quadrature.size(), 1);
    // Standard face orientation: a patch mesh is a structured, consistently
    // oriented grid.
    const Quadrature<dim> cell_points =
      QProjector<dim>::project_to_face(ReferenceCells::get_hypercube<dim>(),
                                       quadrature[0],
                                       face_no);
    compute_at_points(cell,
                      cell_points.get_points(),
                      mapping,
                      mapping_internal,
                      static_cast<const InternalData &>(fe_internal),
                      output_data);
  }



  template <int dim>
  void
  FE_NURBS<dim>::fill_fe_subface_values(
    const typename Triangulation<dim>::cell_iterator &,
    const unsigned int,
    const unsigned int,
    const Quadrature<dim - 1> &,
    const Mapping<dim> &,
    const typename Mapping<dim>::InternalDataBase &,
    const internal::FEValuesImplementation::MappingRelatedData<dim, dim> &,
    const typename FiniteElement<dim>::InternalDataBase &,
    internal::FEValuesImplementation::FiniteElementRelatedData<dim, dim> &)
    const
  {
    AssertThrow(false,
                ExcMessage("FE_NURBS: subfaces (hanging nodes) do not occur "
                           "on a NURBS patch mesh"));
  }

  template class FE_NURBS<2>;
  template class FE_NURBS<3>;
} // namespace isoimpact
