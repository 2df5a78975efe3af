// Layer 3: isogeometric analysis on one NURBS patch.
#include <deal.II/base/exceptions.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/tria.h>

#include <isoimpact/discretization_iga.h>

#include <algorithm>
#include <cmath>

namespace isoimpact
{
  namespace
  {
    nurbs::PatchGeometry<2>
    build_patch(const BodyGeometry &body, const unsigned int degree)
    {
      using Shape = BodyGeometry::Shape;
      nurbs::PatchGeometry<2> geometry;
      switch (body.shape)
        {
          case Shape::half_disk:
            geometry = nurbs::half_disk(body.radius, body.center);
            break;
          case Shape::full_disk:
            geometry = nurbs::full_disk(body.radius, body.center);
            break;
          case Shape::rectangle:
            geometry = nurbs::rectangle(body.lower_left,
                                        body.upper_right,
                                        std::max(degree, 1u));
            break;
        }
      for (unsigned int d = 0; d < 2; ++d)
        {
          const unsigned int present = geometry.patch.degree(d);
          AssertThrow(degree >= present,
                      ExcMessage("IGA degree " + std::to_string(degree) +
                                 " is not allowed for this body: its exact "
                                 "NURBS geometry has degree " +
                                 std::to_string(present) +
                                 " (circles need at least 2)"));
          if (degree > present)
            geometry.patch.elevate_degree(d, degree - present);
        }
      if (body.global_refinements > 0)
        {
          AssertThrow(body.global_refinements < 16,
                      ExcMessage("IGA: too many global refinements (" +
                                 std::to_string(body.global_refinements) +
                                 ")"));
          geometry.patch.refine_uniformly(1u << body.global_refinements);
        }
      if (body.local_refinements > 0 && geometry.has_contact_point)
        for (unsigned int d = 0; d < 2; ++d)
          {
            const auto        &kv  = geometry.patch.knot_vector(d);
            const double       mid = 0.5 * (kv.front() + kv.back());
            const unsigned int side =
              (geometry.contact_parameter[d] > mid) ? 1 : 0;
            geometry.patch.refine_graded(d, side, body.local_refinements, 2.);
          }
      return geometry;
    }

    // Gauss points per direction: p+1 integrate the mass and stiffness of a
    // polynomial (all weights equal) patch with affine geometry exactly.
    // With rational functions the integrands are rational and Gauss
    // quadrature converges exponentially but not exactly; 5 more points
    // give the area of the half disk to 1e-15 relative from 2x2 spans on
    // (also graded), 4e-11 on the single coarse element. Only the set-up
    // (assembly) pays for them.
    template <int dim>
    unsigned int
    quadrature_size(const nurbs::NURBSPatch<dim> &patch)
    {
      unsigned int degree = 0;
      for (unsigned int d = 0; d < dim; ++d)
        degree = std::max(degree, patch.degree(d));
      const auto &weights = patch.weights();
      const auto extremes = std::minmax_element(weights.begin(), weights.end());
      const bool rational =
        *extremes.second - *extremes.first > 1e-14 * *extremes.second;
      return degree + 1 + (rational ? 5 : 0);
    }
  } // namespace



  template <int dim>
  DiscretizationIGA<dim>::DiscretizationIGA(const BodyGeometry &body,
                                            const unsigned int  degree)
    : geometry(build_patch(body, degree))
    , patch(std::make_shared<const nurbs::NURBSPatch<dim>>(geometry.patch))
    , fe(FE_NURBS<dim>(patch), dim)
    , mapping(patch)
    , cell_quadrature(quadrature_size(*patch))
  {
    initialize();
  }



  template <int dim>
  DiscretizationIGA<dim>::DiscretizationIGA(
    const nurbs::PatchGeometry<dim> &patch_geometry)
    : geometry(patch_geometry)
    , patch(std::make_shared<const nurbs::NURBSPatch<dim>>(geometry.patch))
    , fe(FE_NURBS<dim>(patch), dim)
    , mapping(patch)
    , cell_quadrature(quadrature_size(*patch))
  {
    initialize();
  }



  template <int dim>
  void
  DiscretizationIGA<dim>::initialize()
  {
    for (unsigned int f = 0; f < 2 * dim; ++f)
      switch (geometry.side_kinds[f])
        {
          case nurbs::SideKind::arc:
            side_ids[f] = BodyGeometry::curved_boundary_id;
            break;
          case nurbs::SideKind::symmetry:
            side_ids[f] = BodyGeometry::symmetry_boundary_id;
            break;
          default:
            side_ids[f] = f;
        }

    // Vertices: the images of the breakpoints, lexicographic.
    const auto n_elements = patch->n_elements_per_direction();
    std::array<std::vector<double>, dim> breakpoints;
    for (unsigned int d = 0; d < dim; ++d)
      breakpoints[d] = patch->knot_vector(d).breakpoints();
    std::vector<Point<dim>> vertices;
    vertices.reserve((n_elements[0] + 1) * (n_elements[1] + 1));
    for (unsigned int j = 0; j <= n_elements[1]; ++j)
      for (unsigned int i = 0; i <= n_elements[0]; ++i)
        vertices.push_back(
          patch->evaluate(Point<dim>(breakpoints[0][i], breakpoints[1][j])));

    std::vector<CellData<dim>> cells(patch->n_elements());
    for (unsigned int e = 0; e < patch->n_elements(); ++e)
      {
        const auto         index = patch->element_multi_index(e);
        const unsigned int v0    = index[0] + (n_elements[0] + 1) * index[1];
        cells[e].vertices[0]     = v0;
        cells[e].vertices[1]     = v0 + 1;
        cells[e].vertices[2]     = v0 + n_elements[0] + 1;
        cells[e].vertices[3]     = v0 + n_elements[0] + 2;
        cells[e].material_id     = 0;
      }
    triangulation.create_triangulation(vertices, cells, SubCellData());

    // Element index from the first vertex (robust against any reordering of
    // the cells by create_triangulation), then the boundary ids.
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const unsigned int            v0 = cell->vertex_index(0);
        std::array<unsigned int, dim> index;
        index[0] = v0 % (n_elements[0] + 1);
        index[1] = v0 / (n_elements[0] + 1);
        AssertThrow(index[0] < n_elements[0] && index[1] < n_elements[1] &&
                      cell->vertex_index(3) == v0 + n_elements[0] + 2,
                    ExcInternalError());
        cell->set_user_index(patch->element_index(index));
        for (unsigned int f = 0; f < 2 * dim; ++f)
          if (cell->face(f)->at_boundary())
            {
              const unsigned int d = f / 2, s = f % 2;
              AssertThrow((s == 0 && index[d] == 0) ||
                            (s == 1 && index[d] == n_elements[d] - 1),
                          ExcInternalError());
              cell->face(f)->set_boundary_id(side_ids[f]);
            }
      }

    dof_handler.reinit(triangulation);
    dof_handler.distribute_dofs(fe);
  }



  template <int dim>
  std::string
  DiscretizationIGA<dim>::name() const
  {
    return "IGA, " + fe.get_name() + " on " +
           std::to_string(patch->n_elements()) + " knot spans, " +
           std::to_string(patch->n_control_points()) +
           " control points, MappingNURBS";
  }

  template <int dim>
  const Triangulation<dim> &
  DiscretizationIGA<dim>::get_triangulation() const
  {
    return triangulation;
  }

  template <int dim>
  const Mapping<dim> &
  DiscretizationIGA<dim>::get_mapping() const
  {
    return mapping;
  }

  template <int dim>
  const FiniteElement<dim> &
  DiscretizationIGA<dim>::get_fe() const
  {
    return fe;
  }

  template <int dim>
  const DoFHandler<dim> &
  DiscretizationIGA<dim>::get_dof_handler() const
  {
    return dof_handler;
  }

  template <int dim>
  const Quadrature<dim> &
  DiscretizationIGA<dim>::get_cell_quadrature() const
  {
    return cell_quadrature;
  }

  template <int dim>
  types::global_dof_index
  DiscretizationIGA<dim>::n_dofs() const
  {
    return types::global_dof_index(dim) * patch->n_control_points();
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::get_dof_indices(
    const cell_iterator                  &cell,
    std::vector<types::global_dof_index> &indices) const
  {
    thread_local std::vector<unsigned int> control_points;
    patch->element_control_points(cell->user_index(), control_points);
    indices.resize(fe.n_dofs_per_cell());
    for (unsigned int i = 0; i < indices.size(); ++i)
      {
        const auto component_and_function = fe.system_to_component_index(i);
        indices[i]                        = types::global_dof_index(dim) *
                       control_points[component_and_function.second] +
                     component_and_function.first;
      }
  }

  template <int dim>
  unsigned int
  DiscretizationIGA<dim>::dof_component(const types::global_dof_index dof) const
  {
    return dof % dim;
  }

  template <int dim>
  Point<dim>
  DiscretizationIGA<dim>::dof_position(const types::global_dof_index dof) const
  {
    return patch->control_points()[dof / dim];
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::make_constraints(AffineConstraints<double> &) const
  {
    // One patch, no hanging nodes: nothing to constrain.
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::constrain_component_on_boundary(
    const types::boundary_id   boundary_id,
    const unsigned int         component,
    AffineConstraints<double> &constraints) const
  {
    AssertThrow(component < dim, ExcIndexRange(component, 0, dim));
    // The control points of a side alone define the side's curve (open knot
    // vectors), so fixing their component fixes it on the whole side.
    for (unsigned int f = 0; f < 2 * dim; ++f)
      if (side_ids[f] == boundary_id)
        for (const unsigned int a : patch->side_control_points(f))
          {
            const types::global_dof_index dof =
              types::global_dof_index(dim) * a + component;
            if (!constraints.is_constrained(dof))
              constraints.add_line(dof);
          }
  }

  template <int dim>
  std::vector<BoundarySegment<dim>>
  DiscretizationIGA<dim>::boundary_segments(
    const types::boundary_id boundary_id) const
  {
    AssertThrow(dim == 2,
                ExcMessage("boundary segments are implemented for dim = 2"));
    std::vector<BoundarySegment<dim>> segments;
    const auto                       &points  = patch->control_points();
    const auto                       &weights = patch->weights();
    for (unsigned int f = 0; f < 2 * dim; ++f)
      if (side_ids[f] == boundary_id)
        {
          const unsigned int d = f / 2, s = f % 2;
          const unsigned int t          = 1 - d; // direction along the side
          const auto        &kv         = patch->knot_vector(t);
          const auto         extraction = kv.extraction_operators();
          const unsigned int p          = kv.degree();
          const unsigned int fixed_index =
            (s == 0) ? 0 : patch->knot_vector(d).n_basis_functions() - 1;
          const double fixed_parameter = (s == 0) ?
                                           patch->knot_vector(d).front() :
                                           patch->knot_vector(d).back();
          for (unsigned int span = 0; span < kv.n_spans(); ++span)
            {
              BoundarySegment<dim> segment;
              segment.degree = p;
              segment.node_dofs.resize(p + 1);
              segment.node_positions.resize(p + 1);
              segment.node_weights.resize(p + 1);
              for (unsigned int l = 0; l <= p; ++l)
                {
                  std::array<unsigned int, dim> multi_index;
                  multi_index[d] = fixed_index;
                  multi_index[t] = kv.first_basis_function(span) + l;
                  const unsigned int a =
                    patch->control_point_index(multi_index);
                  for (unsigned int c = 0; c < dim; ++c)
                    segment.node_dofs[l][c] =
                      types::global_dof_index(dim) * a + c;
                  segment.node_positions[l] = points[a];
                  segment.node_weights[l]   = weights[a];
                }
              segment.bernstein_coefficients = extraction[span];

              // Orientation: the tangent (increasing eta) rotated by -90
              // degrees against the outward normal cof(J) N at the middle.
              const auto interval = kv.span_interval(span);
              Point<dim> parameter;
              parameter[d] = fixed_parameter;
              parameter[t] = 0.5 * (interval.first + interval.second);
              const auto     jacobian = patch->jacobian(parameter);
              Tensor<2, dim> J;
              for (unsigned int i = 0; i < dim; ++i)
                for (unsigned int j = 0; j < dim; ++j)
                  J[i][j] = jacobian[i][j];
              Tensor<1, dim> unit_normal;
              unit_normal[d]              = (s == 0) ? -1. : 1.;
              const Tensor<1, dim> normal = cofactor(J) * unit_normal;
              std::vector<double>  r, dr;
              evaluate_segment_basis(segment, 0.5, r, dr);
              Tensor<1, dim> tangent;
              for (unsigned int k = 0; k <= p; ++k)
                tangent += dr[k] * segment.node_positions[k];
              Tensor<1, dim> rotated;
              rotated[0]                 = tangent[1];
              rotated[1]                 = -tangent[0];
              segment.normal_orientation = (rotated * normal > 0) ? 1. : -1.;
              segments.push_back(segment);
            }
        }
    mark_free_segment_ends(segments);
    return segments;
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::to_dof_handler_vector(
    const Vector<double> &unknowns,
    Vector<double>       &dof_handler_vector) const
  {
    AssertDimension(unknowns.size(), n_dofs());
    dof_handler_vector.reinit(dof_handler.n_dofs());
    std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> global(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(local);
        get_dof_indices(cell, global);
        for (unsigned int i = 0; i < local.size(); ++i)
          dof_handler_vector[local[i]] = unknowns[global[i]];
      }
  }

  template class DiscretizationIGA<2>;
} // namespace isoimpact
