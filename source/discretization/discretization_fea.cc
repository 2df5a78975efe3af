// Layer 3: classical FEA with deal.II's FE_Q, MappingQ and manifolds.
#include <deal.II/base/exceptions.h>

#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>

#include <deal.II/numerics/vector_tools.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/fe/fe_serendipity.h>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    // The scalar element of the vector-valued one.
    template <int dim>
    std::unique_ptr<FiniteElement<dim>>
    make_scalar_fe(const unsigned int degree, const FEAElement element)
    {
      AssertThrow(degree >= 1,
                  ExcMessage("FEA element degree " + std::to_string(degree) +
                             " is not allowed: the degree must be at least 1"));
      if (element == FEAElement::lagrange)
        return std::make_unique<FE_Q<dim>>(degree);
      AssertThrow(degree == 2,
                  ExcMessage("FEA element 'serendipity' with degree " +
                             std::to_string(degree) +
                             " is not allowed: the serendipity element (Q8) "
                             "exists for degree 2 only; use degree 2 or the "
                             "element 'lagrange' (FE_Q)"));
      return std::make_unique<FE_Serendipity<dim>>(degree);
    }
  } // namespace



  template <int dim>
  DiscretizationFEA<dim>::DiscretizationFEA(const BodyGeometry &geometry,
                                            const unsigned int  degree,
                                            const FEAElement    element)
    // Braces: the element (which checks the degree) is made before the
    // mapping.
    : Discretization<dim>{*make_scalar_fe<dim>(degree, element),
                          std::make_unique<MappingQ<dim>>(degree),
                          degree + 1}
  {
    make_mesh(geometry);
    this->cache_mapping(degree);

    auto &dof_handler = this->dofs;
    dof_handler.reinit(this->mesh);
    dof_handler.distribute_dofs(this->fe());
    // Bandwidth-reducing order: neighbouring unknowns close in memory.
    // (Counted from the arc, its unknowns first, FEA level 7's step took
    // 1.015 and 1.038 times as long on 1 and 2 threads: doc/parallel.md,
    // session 61.)
    DoFRenumbering::Cuthill_McKee(dof_handler);

    std::vector<Point<dim>> support_points(dof_handler.n_dofs());
    DoFTools::map_dofs_to_support_points(this->mapping(),
                                         dof_handler,
                                         support_points);

    std::vector<unsigned char>           components(dof_handler.n_dofs());
    std::vector<types::global_dof_index> indices(this->fe().n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(indices);
        for (unsigned int i = 0; i < indices.size(); ++i)
          components[indices[i]] =
            this->fe().system_to_component_index(i).first;
      }
    this->set_unknowns(std::move(support_points), std::move(components));
  }



  template <int dim>
  void
  DiscretizationFEA<dim>::make_mesh(const BodyGeometry &geometry)
  {
    using Shape = BodyGeometry::Shape;
    const Point<dim> center(geometry.center);
    auto            &triangulation = this->mesh;
    make_coarse_mesh(geometry, triangulation);

    if (geometry.shape != Shape::rectangle)
      {
        // Exact circle on the arc, transfinite interpolation inside so that
        // refined interior cells follow the curved boundary smoothly.
        triangulation.set_all_manifold_ids(1);
        for (const auto &face : triangulation.active_face_iterators())
          if (face->at_boundary() &&
              face->boundary_id() == BodyGeometry::curved_boundary_id)
            face->set_manifold_id(0);
        triangulation.set_manifold(0, SphericalManifold<dim>(center));
        interior_manifold.initialize(triangulation);
        triangulation.set_manifold(1, interior_manifold);
      }

    triangulation.refine_global(geometry.global_refinements);
    const Point<dim> refinement_center(geometry.refinement_center);
    for (unsigned int level = 0; level < geometry.local_refinements; ++level)
      {
        for (const auto &cell : triangulation.active_cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            if (cell->vertex(v).distance(refinement_center) <
                geometry.refinement_radius)
              {
                cell->set_refine_flag();
                break;
              }
        triangulation.execute_coarsening_and_refinement();
      }
  }



  template <int dim>
  std::string
  DiscretizationFEA<dim>::name() const
  {
    // The mapping's degree is the element's (2 for the Q8 element).
    return "FEA, " + this->fe().get_name() + ", MappingQ(" +
           std::to_string(this->fe().degree) + ")";
  }

  template <int dim>
  void
  DiscretizationFEA<dim>::get_dof_indices(
    const cell_iterator                  &cell,
    std::vector<types::global_dof_index> &indices) const
  {
    indices.resize(this->fe().n_dofs_per_cell());
    cell->get_dof_indices(indices);
  }

  template <int dim>
  void
  DiscretizationFEA<dim>::renumber_own_indices(
    const std::vector<types::global_dof_index> &new_numbers)
  {
    this->dofs.renumber_dofs(new_numbers);
  }

  template <int dim>
  void
  DiscretizationFEA<dim>::make_constraints(
    AffineConstraints<double> &constraints) const
  {
    DoFTools::make_hanging_node_constraints(this->dof_handler(), constraints);
  }

  template <int dim>
  void
  DiscretizationFEA<dim>::constrain_component_on_boundary(
    const types::boundary_id   boundary_id,
    const unsigned int         component,
    AffineConstraints<double> &constraints) const
  {
    std::vector<bool> mask(dim, false);
    mask[component] = true;
    VectorTools::interpolate_boundary_values(this->mapping(),
                                             this->dof_handler(),
                                             boundary_id,
                                             Functions::ZeroFunction<dim>(dim),
                                             constraints,
                                             ComponentMask(mask));
  }

  template <int dim>
  std::vector<BoundarySegment<dim>>
  DiscretizationFEA<dim>::unmarked_boundary_segments(
    const types::boundary_id boundary_id) const
  {
    const auto                 &fe       = this->fe();
    const unsigned int          degree   = fe.base_element(0).degree;
    const unsigned int          n_points = degree + 1;
    std::vector<Point<dim - 1>> points(n_points);
    for (unsigned int j = 0; j < n_points; ++j)
      points[j][0] = double(j) / degree;
    const Quadrature<dim - 1> sampling(points,
                                       std::vector<double>(n_points, 1.));
    FEFaceValues<dim>         fe_face_values(this->mapping(),
                                     fe,
                                     sampling,
                                     update_values | update_quadrature_points |
                                       update_normal_vectors);

    std::vector<BoundarySegment<dim>>    segments;
    std::vector<types::global_dof_index> indices(fe.n_dofs_per_cell());
    const auto                          &scalar_fe = fe.base_element(0);
    for (const auto &cell : this->dof_handler().active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            cell->face(f)->boundary_id() == boundary_id)
          {
            fe_face_values.reinit(cell, f);
            cell->get_dof_indices(indices);

            // The scalar functions of the face; the vector element pairs
            // them with each component.
            std::vector<unsigned int> face_functions;
            for (unsigned int i = 0; i < scalar_fe.n_dofs_per_cell(); ++i)
              if (scalar_fe.has_support_on_face(i, f))
                face_functions.push_back(i);

            BoundarySegment<dim> segment;
            segment.degree             = degree;
            const unsigned int n_nodes = face_functions.size();
            segment.node_dofs.resize(n_nodes);
            segment.node_positions.resize(n_nodes);
            segment.node_weights.assign(n_nodes, 1.);
            FullMatrix<double> values(n_nodes, n_points);
            for (unsigned int k = 0; k < n_nodes; ++k)
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const unsigned int i =
                    fe.component_to_system_index(d, face_functions[k]);
                  segment.node_dofs[k][d] = indices[i];
                  if (d == 0)
                    {
                      segment.node_positions[k] =
                        this->dof_position(indices[i]);
                      for (unsigned int j = 0; j < n_points; ++j)
                        values(k, j) =
                          fe_face_values.shape_value_component(i, j, 0);
                    }
                }
            segment.bernstein_coefficients =
              bernstein_coefficients_from_values(values);

            // Orientation: the tangent rotated by -90 degrees against the
            // outward normal deal.II computes, at the middle of the face.
            orient_segment(segment, fe_face_values.normal_vector(n_points / 2));
            segments.push_back(segment);
          }
    return segments;
  }

  template class DiscretizationFEA<2>;
} // namespace isoimpact
