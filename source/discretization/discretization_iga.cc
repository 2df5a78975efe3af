// Layer 3: isogeometric analysis on NURBS patches glued C0.
#include <deal.II/base/exceptions.h>

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <isoimpact/discretization/discretization_iga.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // Gauss points per direction: p+1 integrate the mass and stiffness of a
    // polynomial (all weights equal) patch with affine geometry exactly.
    // With rational functions the integrands are rational and Gauss
    // quadrature converges exponentially but not exactly; 5 more points
    // give the area of the half disk to 1e-15 relative from 2x2 spans on
    // (also graded), 4e-11 on the single coarse element. Only the set-up
    // (assembly) pays for them.
    template <int dim>
    unsigned int
    quadrature_size(const nurbs::MultiPatch<dim> &patches)
    {
      unsigned int degree = 0;
      for (unsigned int d = 0; d < dim; ++d)
        degree = std::max(degree, patches.degree(d));
      const auto &weights = patches.weights();
      const auto extremes = std::minmax_element(weights.begin(), weights.end());
      const bool rational =
        *extremes.second - *extremes.first > 1e-14 * *extremes.second;
      return degree + 1 + (rational ? 5 : 0);
    }
  } // namespace



  template <int dim>
  typename DiscretizationIGA<dim>::PatchSet
  DiscretizationIGA<dim>::make_patches(const BodyGeometry &body,
                                       const unsigned int  degree)
  {
    static_assert(dim == 2, "NURBS bodies are built for dim = 2");
    AssertThrow(body.global_refinements < 16,
                ExcMessage("IGA: Global refinements = " +
                           std::to_string(body.global_refinements) +
                           " is too many; allowed are 0 to 15"));
    const bool curved = body.shape != BodyGeometry::Shape::rectangle;

    Triangulation<2> coarse;
    make_coarse_mesh(body, coarse);
    std::vector<nurbs::NURBSPatch<dim>> patches;
    PatchSet                            result;
    for (const auto &cell : coarse.active_cell_iterators())
      {
        std::array<Point<2>, 4>                 vertices;
        std::array<nurbs::SideKind, 4>          kinds;
        std::array<types::boundary_id, 2 * dim> ids;
        for (unsigned int v = 0; v < 4; ++v)
          vertices[v] = cell->vertex(v);
        for (unsigned int f = 0; f < 4; ++f)
          {
            const auto face = cell->face(f);
            ids[f]          = face->at_boundary() ? face->boundary_id() :
                                                    numbers::internal_face_boundary_id;
            kinds[f]        = nurbs::SideKind::unspecified;
            if (face->at_boundary() && curved &&
                face->boundary_id() == BodyGeometry::curved_boundary_id)
              kinds[f] = nurbs::SideKind::arc;
            else if (face->at_boundary())
              kinds[f] = nurbs::SideKind::straight;
          }
        auto patch = nurbs::quadrilateral(vertices, kinds, body.center).patch;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const unsigned int present = patch.degree(d);
            AssertThrow(degree >= present,
                        ExcMessage("IGA degree " + std::to_string(degree) +
                                   " is not allowed for this body: its exact "
                                   "NURBS geometry has degree " +
                                   std::to_string(present) +
                                   " (circles need at least 2)"));
            if (degree > present)
              patch.elevate_degree(d, degree - present);
          }
        if (body.global_refinements > 0)
          patch.refine_uniformly(1u << body.global_refinements);
        patches.push_back(patch);
        result.side_ids.push_back(ids);
      }

    // Local refinement along knot lines: the direction along a shared face
    // is linked in both cells (deal.II orients the face alike in both).
    std::vector<std::pair<nurbs::KnotLine, nurbs::KnotLine>> links;
    for (const auto &cell : coarse.active_cell_iterators())
      for (unsigned int f = 0; f < 4; ++f)
        if (!cell->at_boundary(f))
          {
            const unsigned int g = cell->neighbor_of_neighbor(f);
            AssertThrow(cell->vertex(
                          GeometryInfo<2>::face_to_cell_vertices(f, 0)) ==
                          cell->neighbor(f)->vertex(
                            GeometryInfo<2>::face_to_cell_vertices(g, 0)),
                        ExcMessage("IGA: two coarse cells run along their "
                                   "shared face in opposite directions; "
                                   "their patches cannot be glued"));
            links.push_back(
              {{cell->active_cell_index(), 1 - f / 2},
               {cell->neighbor(f)->active_cell_index(), 1 - g / 2}});
          }
    nurbs::refine_near_point(patches,
                             links,
                             body.refinement_center,
                             body.refinement_radius,
                             body.local_refinements);
    result.patches = std::make_shared<const nurbs::MultiPatch<dim>>(patches);
    return result;
  }



  template <int dim>
  typename DiscretizationIGA<dim>::PatchSet
  DiscretizationIGA<dim>::make_patches(
    const nurbs::PatchGeometry<dim> &geometry)
  {
    PatchSet result;
    result.patches = std::make_shared<const nurbs::MultiPatch<dim>>(
      std::vector<nurbs::NURBSPatch<dim>>{geometry.patch});
    result.side_ids.emplace_back();
    for (unsigned int f = 0; f < 2 * dim; ++f)
      switch (geometry.side_kinds[f])
        {
          case nurbs::SideKind::arc:
            result.side_ids[0][f] = BodyGeometry::curved_boundary_id;
            break;
          case nurbs::SideKind::symmetry:
            result.side_ids[0][f] = BodyGeometry::symmetry_boundary_id;
            break;
          default:
            result.side_ids[0][f] = f;
        }
    return result;
  }



  template <int dim>
  DiscretizationIGA<dim>::DiscretizationIGA(const BodyGeometry &body,
                                            const unsigned int  degree)
    : DiscretizationIGA(make_patches(body, degree))
  {}



  template <int dim>
  DiscretizationIGA<dim>::DiscretizationIGA(
    const nurbs::PatchGeometry<dim> &patch_geometry)
    : DiscretizationIGA(make_patches(patch_geometry))
  {}



  template <int dim>
  DiscretizationIGA<dim>::DiscretizationIGA(const PatchSet &patch_set)
    : Discretization<dim>(FE_NURBS<dim>(patch_set.patches),
                          std::make_unique<MappingNURBS<dim>>(
                            patch_set.patches),
                          quadrature_size(*patch_set.patches))
    , shared_patches(patch_set.patches)
    , side_ids(patch_set.side_ids)
  {
    make_mesh();
    this->dofs.reinit(this->mesh);
    this->dofs.distribute_dofs(this->fe());

    const types::global_dof_index n_unknowns =
      types::global_dof_index(dim) * patches().n_control_points();
    std::vector<Point<dim>>    positions(n_unknowns);
    std::vector<unsigned char> components(n_unknowns);
    for (types::global_dof_index i = 0; i < n_unknowns; ++i)
      {
        positions[i]  = patches().control_points()[i / dim];
        components[i] = i % dim;
      }
    this->set_unknowns(std::move(positions), std::move(components));
  }



  template <int dim>
  void
  DiscretizationIGA<dim>::make_mesh()
  {
    // Vertices: the images of the breakpoints of every patch, lexicographic;
    // those on interfaces appear twice and are merged below.
    std::vector<Point<dim>>    vertices;
    std::vector<CellData<dim>> cells;
    std::vector<unsigned int>  cell_elements;
    double                     extent = 0.;
    for (unsigned int p = 0; p < patches().n_patches(); ++p)
      {
        const auto        &patch      = patches().patch(p);
        const auto         n_elements = patch.n_elements_per_direction();
        const unsigned int offset     = vertices.size();
        std::array<std::vector<double>, dim> breakpoints;
        for (unsigned int d = 0; d < dim; ++d)
          breakpoints[d] = patch.knot_vector(d).breakpoints();
        for (unsigned int j = 0; j <= n_elements[1]; ++j)
          for (unsigned int i = 0; i <= n_elements[0]; ++i)
            vertices.push_back(
              patch.evaluate(Point<dim>(breakpoints[0][i], breakpoints[1][j])));
        for (unsigned int e = 0; e < patch.n_elements(); ++e)
          {
            const auto         index = patch.element_multi_index(e);
            const unsigned int v0 =
              offset + index[0] + (n_elements[0] + 1) * index[1];
            CellData<dim> cell;
            cell.vertices[0] = v0;
            cell.vertices[1] = v0 + 1;
            cell.vertices[2] = v0 + n_elements[0] + 1;
            cell.vertices[3] = v0 + n_elements[0] + 2;
            cells.push_back(cell);
            cell_elements.push_back(patches().global_element(p, e));
          }
      }
    for (const auto &x : vertices)
      extent = std::max(extent, x.distance(vertices.front()));
    SubCellData               no_subcell_data;
    std::vector<unsigned int> all_vertices;
    GridTools::delete_duplicated_vertices(vertices,
                                          cells,
                                          no_subcell_data,
                                          all_vertices,
                                          1e-10 * extent);
    GridTools::delete_unused_vertices(vertices, cells, no_subcell_data);

    // The element of each cell by its vertices in order (create_triangulation
    // may reorder cells; a reoriented cell would not be found).
    std::map<std::vector<unsigned int>, unsigned int> element_of_vertices;
    for (unsigned int c = 0; c < cells.size(); ++c)
      element_of_vertices[std::vector<unsigned int>(cells[c].vertices.begin(),
                                                    cells[c].vertices.end())] =
        cell_elements[c];
    this->mesh.create_triangulation(vertices, cells, no_subcell_data);

    for (const auto &cell : this->mesh.active_cell_iterators())
      {
        std::vector<unsigned int> key;
        for (const unsigned int v : cell->vertex_indices())
          key.push_back(cell->vertex_index(v));
        const auto found = element_of_vertices.find(key);
        AssertThrow(found != element_of_vertices.end(),
                    ExcMessage("IGA mesh: a cell was reoriented by the "
                               "triangulation; the patches are not "
                               "consistently oriented"));
        cell->set_user_index(found->second);
        const auto [p, e]    = patches().local_element(found->second);
        const auto index     = patches().patch(p).element_multi_index(e);
        const auto n_per_dir = patches().patch(p).n_elements_per_direction();
        for (unsigned int f = 0; f < 2 * dim; ++f)
          if (cell->face(f)->at_boundary())
            {
              const unsigned int d = f / 2, s = f % 2;
              AssertThrow(((s == 0 && index[d] == 0) ||
                           (s == 1 && index[d] == n_per_dir[d] - 1)) &&
                            side_ids[p][f] !=
                              numbers::internal_face_boundary_id,
                          ExcInternalError());
              cell->face(f)->set_boundary_id(side_ids[p][f]);
            }
      }
  }



  template <int dim>
  std::string
  DiscretizationIGA<dim>::name() const
  {
    return "IGA, " + this->fe().get_name() + " on " +
           std::to_string(patches().n_patches()) + " patch" +
           (patches().n_patches() > 1 ? "es, " : ", ") +
           std::to_string(patches().n_elements()) + " knot spans, " +
           std::to_string(patches().n_control_points()) +
           " control points, MappingNURBS";
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::get_dof_indices(
    const cell_iterator                  &cell,
    std::vector<types::global_dof_index> &indices) const
  {
    thread_local std::vector<unsigned int> control_points;
    patches().element_control_points(cell->user_index(), control_points);
    indices.resize(this->fe().n_dofs_per_cell());
    for (unsigned int i = 0; i < indices.size(); ++i)
      {
        const auto component_and_function =
          this->fe().system_to_component_index(i);
        indices[i] = unknown(types::global_dof_index(dim) *
                               control_points[component_and_function.second] +
                             component_and_function.first);
      }
  }

  template <int dim>
  HigherOrderCell
  DiscretizationIGA<dim>::higher_order_cell(const cell_iterator &cell) const
  {
    AssertThrow(dim == 2,
                ExcMessage("higher-order VTK cells are implemented for "
                           "dim = 2"));
    if (bezier_cells.empty())
      {
        const unsigned int p = patches().degree(0);
        for (unsigned int d = 1; d < dim; ++d)
          AssertThrow(patches().degree(d) == p,
                      ExcMessage("Bezier output needs equal degrees in all "
                                 "directions"));
        const auto                nodes = vtk_node_points(p);
        const unsigned int        n     = nodes.size();
        std::vector<unsigned int> bernstein(n); // lexicographic index
        for (unsigned int j = 0; j < n; ++j)
          bernstein[j] = std::lround(nodes[j][0] * p) +
                         (p + 1) * std::lround(nodes[j][1] * p);
        // B_b(x_k), lexicographic b.
        FullMatrix<double>  B(n, n);
        std::vector<double> b0(p + 1), b1(p + 1);
        for (unsigned int k = 0; k < n; ++k)
          {
            nurbs::KnotVector::bernstein_values(p, nodes[k][0], b0.data());
            nurbs::KnotVector::bernstein_values(p, nodes[k][1], b1.data());
            for (unsigned int b = 0; b < n; ++b)
              B(k, b) = b0[b % (p + 1)] * b1[b / (p + 1)];
          }
        bezier_cells.resize(patches().n_elements());
        for (unsigned int e = 0; e < patches().n_elements(); ++e)
          {
            const auto [patch_number, element] = patches().local_element(e);
            const auto      &patch             = patches().patch(patch_number);
            const auto       C = patch.element_extraction_operator(element);
            const auto       indices = patch.element_control_points(element);
            HigherOrderCell &result  = bezier_cells[e];
            result.vtk_type          = HigherOrderCell::bezier_quadrilateral;
            result.degree            = p;
            result.weights.assign(n, 0.);
            // w_b = sum_a C(a, b) w_a, in VTK's node order.
            for (unsigned int j = 0; j < n; ++j)
              for (unsigned int a = 0; a < n; ++a)
                result.weights[j] +=
                  C(a, bernstein[j]) * patch.weights()[indices[a]];
            // A(k, j) = w_j B_j(x_k) / W(x_k); values_to_nodes = A^-1.
            FullMatrix<double> A(n, n);
            for (unsigned int k = 0; k < n; ++k)
              {
                double W = 0.;
                for (unsigned int j = 0; j < n; ++j)
                  W += result.weights[j] * B(k, bernstein[j]);
                for (unsigned int j = 0; j < n; ++j)
                  A(k, j) = result.weights[j] * B(k, bernstein[j]) / W;
              }
            result.values_to_nodes.reinit(n, n);
            result.values_to_nodes.invert(A);
          }
      }
    return bezier_cells[cell->user_index()];
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
    for (unsigned int p = 0; p < patches().n_patches(); ++p)
      for (unsigned int f = 0; f < 2 * dim; ++f)
        if (side_ids[p][f] == boundary_id)
          for (const unsigned int a : patches().patch(p).side_control_points(f))
            {
              const types::global_dof_index dof =
                unknown(types::global_dof_index(dim) *
                          patches().global_control_point(p, a) +
                        component);
              if (!constraints.is_constrained(dof))
                constraints.add_line(dof);
            }
  }

  template <int dim>
  std::vector<BoundarySegment<dim>>
  DiscretizationIGA<dim>::unmarked_boundary_segments(
    const types::boundary_id boundary_id) const
  {
    std::vector<BoundarySegment<dim>> segments;
    for (unsigned int p = 0; p < patches().n_patches(); ++p)
      for (unsigned int f = 0; f < 2 * dim; ++f)
        if (side_ids[p][f] == boundary_id)
          {
            const auto        &patch   = patches().patch(p);
            const auto        &points  = patch.control_points();
            const auto        &weights = patch.weights();
            const unsigned int d = f / 2, s = f % 2;
            const unsigned int t          = 1 - d; // direction along the side
            const auto        &kv         = patch.knot_vector(t);
            const auto         extraction = kv.extraction_operators();
            const unsigned int degree     = kv.degree();
            const unsigned int fixed_index =
              (s == 0) ? 0 : patch.knot_vector(d).n_basis_functions() - 1;
            const double fixed_parameter = (s == 0) ?
                                             patch.knot_vector(d).front() :
                                             patch.knot_vector(d).back();
            for (unsigned int span = 0; span < kv.n_spans(); ++span)
              {
                BoundarySegment<dim> segment;
                segment.degree = degree;
                segment.node_dofs.resize(degree + 1);
                segment.node_positions.resize(degree + 1);
                segment.node_weights.resize(degree + 1);
                for (unsigned int l = 0; l <= degree; ++l)
                  {
                    std::array<unsigned int, dim> multi_index;
                    multi_index[d] = fixed_index;
                    multi_index[t] = kv.first_basis_function(span) + l;
                    const unsigned int a =
                      patch.control_point_index(multi_index);
                    for (unsigned int c = 0; c < dim; ++c)
                      segment.node_dofs[l][c] =
                        unknown(types::global_dof_index(dim) *
                                  patches().global_control_point(p, a) +
                                c);
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
                const auto     jacobian = patch.jacobian(parameter);
                Tensor<2, dim> J;
                for (unsigned int i = 0; i < dim; ++i)
                  for (unsigned int j = 0; j < dim; ++j)
                    J[i][j] = jacobian[i][j];
                Tensor<1, dim> unit_normal;
                unit_normal[d] = (s == 0) ? -1. : 1.;
                orient_segment(segment,
                               Tensor<1, dim>(cofactor(J) * unit_normal));
                segments.push_back(segment);
              }
          }
    return segments;
  }

  template <int dim>
  void
  DiscretizationIGA<dim>::renumber_own_indices(
    const std::vector<types::global_dof_index> &new_numbers)
  {
    if (renumbered.empty())
      renumbered = new_numbers;
    else
      for (auto &number : renumbered)
        number = new_numbers[number];
  }

  template class DiscretizationIGA<2>;
} // namespace isoimpact
