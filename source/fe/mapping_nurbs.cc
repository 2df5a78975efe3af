// Layer 2: exact NURBS geometry as a deal.II Mapping.
#include <deal.II/base/exceptions.h>
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/memory_consumption.h>
#include <deal.II/base/qprojector.h>

#include <deal.II/fe/fe_update_flags.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/reference_cell.h>
#include <deal.II/grid/tria.h>

#include <isoimpact/fe/mapping_nurbs.h>

#include <cmath>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // x = sum_a R_a P_a and J = sum_a P_a (x) dR_a/dreference over the
    // element's control points.
    template <int dim>
    void
    position_and_jacobian(const std::vector<Point<dim>>   &control_points,
                          const std::vector<unsigned int> &indices,
                          const double                    *values,
                          const Tensor<1, dim>            *gradients,
                          Point<dim>                      &x,
                          Tensor<2, dim>                  &jacobian)
    {
      x        = Point<dim>();
      jacobian = Tensor<2, dim>();
      for (unsigned int a = 0; a < indices.size(); ++a)
        {
          const Point<dim> &P = control_points[indices[a]];
          for (unsigned int i = 0; i < dim; ++i)
            {
              x[i] += values[a] * P[i];
              for (unsigned int j = 0; j < dim; ++j)
                jacobian[i][j] += P[i] * gradients[a][j];
            }
        }
    }
  } // namespace

  namespace
  {
    template <int dim>
    unsigned int
    element_of(const typename Triangulation<dim>::cell_iterator &cell,
               const nurbs::MultiPatch<dim>                     &patches)
    {
      const unsigned int element = cell->user_index();
      AssertThrow(element < patches.n_elements(),
                  ExcMessage("MappingNURBS: the cell's user_index " +
                             std::to_string(element) +
                             " is not an element of the patches (0 to " +
                             std::to_string(patches.n_elements()) + "-1)"));
      return element;
    }
  } // namespace



  template <int dim>
  void
  MappingNURBS<dim>::InternalData::resize(const unsigned int n_points) const
  {
    jacobians.resize(n_points);
    covariant.resize(n_points);
    determinants.resize(n_points);
  }



  template <int dim>
  std::size_t
  MappingNURBS<dim>::InternalData::memory_consumption() const
  {
    return Mapping<dim>::InternalDataBase::memory_consumption() +
           MemoryConsumption::memory_consumption(jacobians) +
           MemoryConsumption::memory_consumption(covariant) +
           MemoryConsumption::memory_consumption(determinants) +
           MemoryConsumption::memory_consumption(values) +
           MemoryConsumption::memory_consumption(gradients) +
           MemoryConsumption::memory_consumption(control_points);
  }



  template <int dim>
  MappingNURBS<dim>::MappingNURBS(
    const std::shared_ptr<const nurbs::NURBSPatch<dim>> &patch)
    : MappingNURBS(nurbs::as_multipatch(patch))
  {}



  template <int dim>
  MappingNURBS<dim>::MappingNURBS(
    const std::shared_ptr<const nurbs::MultiPatch<dim>> &patches)
    : shared_patches(patches)
  {
    AssertThrow(patches != nullptr, ExcMessage("MappingNURBS: no patch given"));
  }



  template <int dim>
  std::unique_ptr<Mapping<dim>>
  MappingNURBS<dim>::clone() const
  {
    return std::make_unique<MappingNURBS<dim>>(shared_patches);
  }



  template <int dim>
  bool
  MappingNURBS<dim>::is_compatible_with(
    const ReferenceCell &reference_cell) const
  {
    return reference_cell == ReferenceCells::get_hypercube<dim>();
  }



  template <int dim>
  void
  MappingNURBS<dim>::evaluate(const unsigned int  element,
                              const Point<dim>   &unit_point,
                              const InternalData &data,
                              Point<dim>         &x,
                              Tensor<2, dim>     &jacobian) const
  {
    shared_patches->element_control_points(element, data.control_points);
    shared_patches->element_rational_basis(element,
                                           unit_point,
                                           data.values,
                                           data.gradients);
    position_and_jacobian<dim>(shared_patches->control_points(),
                               data.control_points,
                               data.values.data(),
                               data.gradients.data(),
                               x,
                               jacobian);
  }



  template <int dim>
  boost::container::small_vector<Point<dim>,
                                 GeometryInfo<dim>::vertices_per_cell>
  MappingNURBS<dim>::get_vertices(
    const typename Triangulation<dim>::cell_iterator &cell) const
  {
    boost::container::small_vector<Point<dim>,
                                   GeometryInfo<dim>::vertices_per_cell>
      vertices;
    for (unsigned int v = 0; v < GeometryInfo<dim>::vertices_per_cell; ++v)
      vertices.push_back(
        transform_unit_to_real_cell(cell,
                                    GeometryInfo<dim>::unit_cell_vertex(v)));
    return vertices;
  }



  template <int dim>
  Point<dim>
  MappingNURBS<dim>::transform_unit_to_real_cell(
    const typename Triangulation<dim>::cell_iterator &cell,
    const Point<dim>                                 &p) const
  {
    InternalData   data;
    Point<dim>     x;
    Tensor<2, dim> jacobian;
    evaluate(element_of<dim>(cell, *shared_patches), p, data, x, jacobian);
    return x;
  }



  template <int dim>
  Point<dim>
  MappingNURBS<dim>::transform_real_to_unit_cell(
    const typename Triangulation<dim>::cell_iterator &cell,
    const Point<dim>                                 &p) const
  {
    const unsigned int element = element_of<dim>(cell, *shared_patches);
    InternalData       data;
    Point<dim>         xi;
    for (unsigned int d = 0; d < dim; ++d)
      xi[d] = 0.5;
    Point<dim>     x;
    Tensor<2, dim> jacobian;
    evaluate(element, xi, data, x, jacobian);
    const double scale = cell->diameter();
    for (unsigned int iteration = 0; iteration < 100; ++iteration)
      {
        const Tensor<1, dim> residual = p - x;
        if (residual.norm() <= 1e-13 * scale)
          return xi;
        const double det = determinant(jacobian);
        if (!(std::abs(det) > 0.) || !std::isfinite(det))
          break;
        const Tensor<1, dim> step = invert(jacobian) * residual;
        // Damped step: keep the iterate within a generous box around the
        // cell so that the polynomial extension stays meaningful.
        double factor = 1.;
        for (unsigned int d = 0; d < dim; ++d)
          if (std::abs(step[d]) > 1.)
            factor = std::min(factor, 1. / std::abs(step[d]));
        xi += factor * step;
        for (unsigned int d = 0; d < dim; ++d)
          if (!std::isfinite(xi[d]) || std::abs(xi[d] - 0.5) > 10.)
            AssertThrow(false,
                        (typename Mapping<dim>::ExcTransformationFailed()));
        evaluate(element, xi, data, x, jacobian);
      }
    if ((p - x).norm() <= 1e-11 * scale)
      return xi;
    AssertThrow(false, (typename Mapping<dim>::ExcTransformationFailed()));
    return xi;
  }



  template <int dim>
  UpdateFlags
  MappingNURBS<dim>::requires_update_flags(const UpdateFlags in) const
  {
    UpdateFlags out = in;
    if (in & update_normal_vectors)
      out |= update_boundary_forms;
    return out;
  }



  template <int dim>
  std::unique_ptr<typename Mapping<dim>::InternalDataBase>
  MappingNURBS<dim>::get_data(const UpdateFlags      update_flags,
                              const Quadrature<dim> &quadrature) const
  {
    auto data         = std::make_unique<InternalData>();
    data->update_each = requires_update_flags(update_flags);
    data->resize(quadrature.size());
    return data;
  }



  template <int dim>
  std::unique_ptr<typename Mapping<dim>::InternalDataBase>
  MappingNURBS<dim>::get_face_data(
    const UpdateFlags               update_flags,
    const hp::QCollection<dim - 1> &quadrature) const
  {
    auto data         = std::make_unique<InternalData>();
    data->update_each = requires_update_flags(update_flags);
    unsigned int n    = 0;
    for (unsigned int i = 0; i < quadrature.size(); ++i)
      n = std::max<unsigned int>(n, quadrature[i].size());
    data->resize(n);
    return data;
  }



  template <int dim>
  std::unique_ptr<typename Mapping<dim>::InternalDataBase>
  MappingNURBS<dim>::get_subface_data(const UpdateFlags,
                                      const Quadrature<dim - 1> &) const
  {
    AssertThrow(false,
                ExcMessage("MappingNURBS: subfaces (hanging nodes) do not "
                           "occur on a NURBS patch mesh"));
    return nullptr;
  }



  template <int dim>
  void
  MappingNURBS<dim>::compute_at_points(
    const typename Triangulation<dim>::cell_iterator               &cell,
    const std::vector<Point<dim>>                                  &points,
    const InternalData                                             &data,
    internal::FEValuesImplementation::MappingRelatedData<dim, dim> &output_data)
    const
  {
    const unsigned int element = element_of<dim>(cell, *shared_patches);
    const UpdateFlags  flags   = data.update_each;
    if (data.jacobians.size() < points.size())
      data.resize(points.size());
    // The basis at all points at once (NURBSPatch::element_rational_basis).
    shared_patches->element_control_points(element, data.control_points);
    shared_patches->element_rational_basis(element,
                                           points,
                                           data.values,
                                           data.gradients);
    const unsigned int n = data.control_points.size();
    for (unsigned int q = 0; q < points.size(); ++q)
      {
        Point<dim>     x;
        Tensor<2, dim> J;
        position_and_jacobian<dim>(shared_patches->control_points(),
                                   data.control_points,
                                   &data.values[q * n],
                                   &data.gradients[q * n],
                                   x,
                                   J);
        const double det     = determinant(J);
        data.jacobians[q]    = J;
        data.determinants[q] = det;
        data.covariant[q] =
          (det != 0.) ? transpose(invert(J)) : Tensor<2, dim>();
        if (flags & update_quadrature_points)
          output_data.quadrature_points[q] = x;
        if (flags & update_jacobians)
          for (unsigned int i = 0; i < dim; ++i)
            for (unsigned int j = 0; j < dim; ++j)
              output_data.jacobians[q][i][j] = J[i][j];
        if (flags & update_inverse_jacobians)
          {
            // inverse_jacobians[q][i][j] = d xhat_i / d x_j
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = 0; j < dim; ++j)
                output_data.inverse_jacobians[q][i][j] =
                  data.covariant[q][j][i];
          }
      }
  }



  template <int dim>
  CellSimilarity::Similarity
  MappingNURBS<dim>::fill_fe_values(
    const typename Triangulation<dim>::cell_iterator &cell,
    const CellSimilarity::Similarity,
    const Quadrature<dim>                         &quadrature,
    const typename Mapping<dim>::InternalDataBase &internal_data,
    internal::FEValuesImplementation::MappingRelatedData<dim, dim> &output_data)
    const
  {
    Assert(dynamic_cast<const InternalData *>(&internal_data) != nullptr,
           ExcInternalError());
    const auto &data = static_cast<const InternalData &>(internal_data);
    compute_at_points(cell, quadrature.get_points(), data, output_data);
    AssertThrow(!(data.update_each & (update_jacobian_grads |
                                      update_jacobian_pushed_forward_grads |
                                      update_jacobian_2nd_derivatives |
                                      update_jacobian_3rd_derivatives)),
                ExcMessage("MappingNURBS: derivatives of the Jacobian are "
                           "not implemented"));
    if (data.update_each & update_JxW_values)
      for (unsigned int q = 0; q < quadrature.size(); ++q)
        output_data.JxW_values[q] = data.determinants[q] * quadrature.weight(q);
    // Knot spans with equal corners may differ in their weights: never let
    // FEValues reuse the data for the next cell.
    return CellSimilarity::invalid_next_cell;
  }



  template <int dim>
  void
  MappingNURBS<dim>::fill_fe_face_values(
    const typename Triangulation<dim>::cell_iterator &cell,
    const unsigned int                                face_no,
    const hp::QCollection<dim - 1>                   &quadrature_collection,
    const typename Mapping<dim>::InternalDataBase    &internal_data,
    internal::FEValuesImplementation::MappingRelatedData<dim, dim> &output_data)
    const
  {
    Assert(dynamic_cast<const InternalData *>(&internal_data) != nullptr,
           ExcInternalError());
    AssertDimension(quadrature_collection.size(), 1);
    const auto &data       = static_cast<const InternalData &>(internal_data);
    const auto &quadrature = quadrature_collection[0];
    const Quadrature<dim> cell_points =
      QProjector<dim>::project_to_face(ReferenceCells::get_hypercube<dim>(),
                                       quadrature,
                                       face_no);
    compute_at_points(cell, cell_points.get_points(), data, output_data);

    const UpdateFlags flags = data.update_each;
    if (flags &
        (update_boundary_forms | update_normal_vectors | update_JxW_values))
      {
        const Tensor<1, dim> unit_normal =
          GeometryInfo<dim>::unit_normal_vector[face_no];
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            // Nanson: boundary form = det(J) J^{-T} N = cof(J) N.
            const Tensor<1, dim> form =
              cofactor(data.jacobians[q]) * unit_normal;
            const double area = form.norm();
            if (flags & update_boundary_forms)
              output_data.boundary_forms[q] = form;
            if (flags & update_normal_vectors)
              output_data.normal_vectors[q] = form / area;
            if (flags & update_JxW_values)
              output_data.JxW_values[q] = area * quadrature.weight(q);
          }
      }
  }



  template <int dim>
  void
  MappingNURBS<dim>::fill_fe_subface_values(
    const typename Triangulation<dim>::cell_iterator &,
    const unsigned int,
    const unsigned int,
    const Quadrature<dim - 1> &,
    const typename Mapping<dim>::InternalDataBase &,
    internal::FEValuesImplementation::MappingRelatedData<dim, dim> &) const
  {
    AssertThrow(false,
                ExcMessage("MappingNURBS: subfaces (hanging nodes) do not "
                           "occur on a NURBS patch mesh"));
  }



  template <int dim>
  void
  MappingNURBS<dim>::transform(
    const ArrayView<const Tensor<1, dim>>         &input,
    const MappingKind                              kind,
    const typename Mapping<dim>::InternalDataBase &internal,
    const ArrayView<Tensor<1, dim>>               &output) const
  {
    const auto &data = static_cast<const InternalData &>(internal);
    AssertDimension(input.size(), output.size());
    Assert(input.size() <= data.jacobians.size(),
           ExcIndexRange(input.size(), 0, data.jacobians.size() + 1));
    switch (kind)
      {
        case mapping_contravariant:
          for (unsigned int q = 0; q < input.size(); ++q)
            output[q] = data.jacobians[q] * input[q];
          return;
        case mapping_covariant:
          for (unsigned int q = 0; q < input.size(); ++q)
            output[q] = data.covariant[q] * input[q];
          return;
        case mapping_piola:
          for (unsigned int q = 0; q < input.size(); ++q)
            output[q] = data.jacobians[q] * input[q] / data.determinants[q];
          return;
        default:
          AssertThrow(false, ExcNotImplemented());
      }
  }



  namespace
  {
    template <int dim>
    void
    transform_rank_2(const std::vector<Tensor<2, dim>> &jacobians,
                     const std::vector<Tensor<2, dim>> &covariant,
                     const std::vector<double>         &determinants,
                     const Tensor<2, dim>              &in,
                     const unsigned int                 q,
                     const MappingKind                  kind,
                     Tensor<2, dim>                    &out)
    {
      switch (kind)
        {
          case mapping_contravariant:
            out = jacobians[q] * in;
            return;
          case mapping_covariant:
            out = covariant[q] * in;
            return;
          case mapping_covariant_gradient:
            out = covariant[q] * in * transpose(covariant[q]);
            return;
          case mapping_contravariant_gradient:
            out = jacobians[q] * in * transpose(covariant[q]);
            return;
          case mapping_piola_gradient:
            out = jacobians[q] * in * transpose(covariant[q]) / determinants[q];
            return;
          default:
            AssertThrow(false, ExcNotImplemented());
        }
    }
  } // namespace



  template <int dim>
  void
  MappingNURBS<dim>::transform(
    const ArrayView<const DerivativeForm<1, dim, dim>> &input,
    const MappingKind                                   kind,
    const typename Mapping<dim>::InternalDataBase      &internal,
    const ArrayView<Tensor<2, dim>>                    &output) const
  {
    const auto &data = static_cast<const InternalData &>(internal);
    AssertDimension(input.size(), output.size());
    for (unsigned int q = 0; q < input.size(); ++q)
      {
        Tensor<2, dim> in;
        for (unsigned int i = 0; i < dim; ++i)
          for (unsigned int j = 0; j < dim; ++j)
            in[i][j] = input[q][i][j];
        transform_rank_2(data.jacobians,
                         data.covariant,
                         data.determinants,
                         in,
                         q,
                         kind,
                         output[q]);
      }
  }



  template <int dim>
  void
  MappingNURBS<dim>::transform(
    const ArrayView<const Tensor<2, dim>>         &input,
    const MappingKind                              kind,
    const typename Mapping<dim>::InternalDataBase &internal,
    const ArrayView<Tensor<2, dim>>               &output) const
  {
    const auto &data = static_cast<const InternalData &>(internal);
    AssertDimension(input.size(), output.size());
    for (unsigned int q = 0; q < input.size(); ++q)
      transform_rank_2(data.jacobians,
                       data.covariant,
                       data.determinants,
                       input[q],
                       q,
                       kind,
                       output[q]);
  }



  template <int dim>
  void
  MappingNURBS<dim>::transform(
    const ArrayView<const DerivativeForm<2, dim, dim>> &,
    const MappingKind,
    const typename Mapping<dim>::InternalDataBase &,
    const ArrayView<Tensor<3, dim>> &) const
  {
    AssertThrow(false,
                ExcMessage("MappingNURBS: rank-3 transforms (second "
                           "derivatives) are not implemented"));
  }



  template <int dim>
  void
  MappingNURBS<dim>::transform(const ArrayView<const Tensor<3, dim>> &,
                               const MappingKind,
                               const typename Mapping<dim>::InternalDataBase &,
                               const ArrayView<Tensor<3, dim>> &) const
  {
    AssertThrow(false,
                ExcMessage("MappingNURBS: rank-3 transforms (second "
                           "derivatives) are not implemented"));
  }

  template class MappingNURBS<2>;
  template class MappingNURBS<3>;
} // namespace isoimpact
