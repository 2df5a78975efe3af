// The 8-node serendipity quadrilateral FE_Serendipity<2> (Q8).
// 1. The element against FE_Q(2) on faces: same face dofs, support points,
//    traces and interface (hanging-node) constraints, to 1e-14 (exact
//    numbers built from a Vandermonde inverse: round-off only); the
//    prolongation matrices map the nodal values of a quadratic to those on
//    the children (1e-14).
// 2. One undistorted element through the project's assembly (DiscretizationFEA
//    with FEAElement::serendipity), per displacement component, as fractions
//    of the element mass m_e = rho * area (exact values, e.g. Hughes, The
//    Finite Element Method, ch. 7):
//      consistent diagonal: corner 1/30,  mid-side 8/45,
//      HRZ:                 corner 3/76,  mid-side 16/76,
//      row sums:            corner -1/12, mid-side 1/3,
//    tolerance 1e-13 (relative): the 3x3 Gauss rule of the discretisation
//    integrates products of serendipity functions (degree <= 4 per
//    direction) exactly on an affine cell, so only round-off remains. The
//    project's row-sum lumping must refuse the element: the error names the
//    scheme and the negative fraction -1/12 = -0.0833333.
// 3. Interpolation (VectorTools::interpolate, MappingQ(2)): a complete
//    quadratic is reproduced on a mesh of parallelograms (affinely
//    distorted): L2 error < 1e-12 relative to its L2 norm; x^2 y^2 is not
//    (relative error asserted > 1e-4). On a mesh of trapezoids (bilinear
//    cell maps) Q8 does not reproduce a quadratic either (a known property
//    of serendipity elements; asserted > 1e-6 as a control of the
//    measurement), whereas it does reproduce a linear field (< 1e-12). DataOut
//    writes the field (VTU size > 0).
// 4. Hanging nodes (DoFTools::make_hanging_node_constraints) on a locally
//    refined parallelogram mesh: the interpolated quadratic already
//    satisfies the constraints (|u - distribute(u)| < 1e-12), and a field
//    that is not in the space (x^2 y^2) becomes continuous across hanging
//    faces after distribute() (jump < 1e-12; before: > 1e-6 as control).
// 5. The patch test of test_helpers.h (check_patch_test) for
//    FESystem(FE_Serendipity, 2) elasticity through
//    create_discretization("fea", ..., 2, FEAElement::serendipity): a linear
//    displacement field gives the exact strain energy 0.5 V sigma : eps to
//    1e-12 relative (V from integrate_mass), and a rigid motion none, on a
//    rectangle, a locally refined rectangle (hanging nodes) and the half disk
//    (curved cells, MappingQ(2)). Residuals, strain, stress and values in
//    the cells equal the exact ones to 1e-12 relative on the rectangles
//    (strain measured 1.4e-14, 2.3e-14). On the half
//    disk 1e-10: measured 2.7e-11, the same pull-back tolerance of
//    TransfiniteInterpolationManifold as in tests/patch_test.cc (FE_Q(2):
//    5e-11). Note that the strain energy alone is a weak check on curved
//    cells: a field error that vanishes on the cell boundary (a bubble, the
//    part of a biquadratic mapping Q8 cannot represent) changes the energy
//    of a constant strain only to second order; hence the pointwise check.
// 6. Contact segments of the half disk's arc with Q8: as many as with FE_Q(2),
//    three nodes each, the curve through its nodes (1e-13).
#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <isoimpact/discretization/discretization_fea.h>
#include <isoimpact/fe/fe_serendipity.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <cmath>
#include <sstream>
#include <string>

#include "test_helpers.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  // A complete quadratic, a linear field and x^2 y^2.
  class Field : public Function<2>
  {
  public:
    enum Kind
    {
      quadratic,
      linear,
      x2y2
    };
    explicit Field(const Kind kind)
      : kind(kind)
    {}
    double
    value(const Point<2> &p, const unsigned int = 0) const override
    {
      const double x = p[0], y = p[1];
      switch (kind)
        {
          case quadratic:
            return 1.5 - 0.7 * x + 0.4 * y + 0.9 * x * x - 1.1 * x * y +
                   0.6 * y * y;
          case linear:
            return 1.5 - 0.7 * x + 0.4 * y;
          default:
            return x * x * y * y;
        }
    }

  private:
    const Kind kind;
  };

  // 3 x 3 cells on [0,1]^2, then mapped: affine (parallelograms) or
  // bilinear (trapezoids).
  void
  make_distorted_mesh(Triangulation<2> &tria, const bool affine)
  {
    GridGenerator::subdivided_hyper_cube(tria, 3, 0., 1.);
    GridTools::transform(
      [affine](const Point<2> &p) {
        if (affine)
          return Point<2>(0.3 + 1.2 * p[0] + 0.5 * p[1],
                          -0.2 + 0.3 * p[0] + 0.9 * p[1]);
        return Point<2>(p[0], p[1] * (1. + 0.6 * p[0]));
      },
      tria);
  }

  // Relative L2 error of the interpolant of `field`.
  double
  interpolation_error(const DoFHandler<2> &dof_handler,
                      const Mapping<2>    &mapping,
                      const Field         &field,
                      Vector<double>      &u)
  {
    u.reinit(dof_handler.n_dofs());
    VectorTools::interpolate(mapping, dof_handler, field, u);
    Vector<float> cell_errors(dof_handler.get_triangulation().n_active_cells());
    VectorTools::integrate_difference(mapping,
                                      dof_handler,
                                      u,
                                      field,
                                      cell_errors,
                                      QGauss<2>(5),
                                      VectorTools::L2_norm);
    Vector<double> zero(dof_handler.n_dofs());
    Vector<float>  cell_norms(cell_errors.size());
    VectorTools::integrate_difference(mapping,
                                      dof_handler,
                                      zero,
                                      field,
                                      cell_norms,
                                      QGauss<2>(5),
                                      VectorTools::L2_norm);
    const Triangulation<2> &tria = dof_handler.get_triangulation();
    return VectorTools::compute_global_error(tria,
                                             cell_errors,
                                             VectorTools::L2_norm) /
           VectorTools::compute_global_error(tria,
                                             cell_norms,
                                             VectorTools::L2_norm);
  }

  void
  check_element_against_fe_q()
  {
    std::cout << "--- FE_Serendipity<2> against FE_Q<2>(2) on faces"
              << std::endl;
    const FE_Serendipity<2> q8;
    const FE_Q<2>           q9(2);
    CHECK_TRUE(q8.get_name() == "FE_Serendipity<2>(2)");
    CHECK_TRUE(q8.clone()->get_name() == "FE_Serendipity<2>(2)");
    CHECK_TRUE(q8.n_dofs_per_cell() == 8 && q8.n_dofs_per_vertex() == 1 &&
               q8.n_dofs_per_line() == 1 && q8.n_dofs_per_quad(0) == 0);
    CHECK_TRUE(q8.n_dofs_per_face(0) == q9.n_dofs_per_face(0));

    // Nodal basis at the support points.
    double delta_error = 0.;
    for (unsigned int i = 0; i < 8; ++i)
      for (unsigned int j = 0; j < 8; ++j)
        delta_error =
          std::max(delta_error,
                   std::abs(q8.shape_value(j, q8.get_unit_support_points()[i]) -
                            (i == j ? 1. : 0.)));
    CHECK_CLOSE_ABS(delta_error, 0., 1e-14);

    // Interface constraints and face support points.
    const FullMatrix<double> &c8 = q8.constraints();
    const FullMatrix<double> &c9 = q9.constraints();
    CHECK_TRUE(c8.m() == c9.m() && c8.n() == c9.n());
    double constraint_difference = 0.;
    for (unsigned int i = 0; i < c8.m(); ++i)
      for (unsigned int j = 0; j < c8.n(); ++j)
        constraint_difference =
          std::max(constraint_difference, std::abs(c8(i, j) - c9(i, j)));
    CHECK_CLOSE_ABS(constraint_difference, 0., 1e-14);
    double face_point_difference = 0.;
    for (unsigned int j = 0; j < q8.n_dofs_per_face(0); ++j)
      face_point_difference =
        std::max(face_point_difference,
                 q8.get_unit_face_support_points(0)[j].distance(
                   q9.get_unit_face_support_points(0)[j]));
    CHECK_CLOSE_ABS(face_point_difference, 0., 1e-14);

    // Traces: face function j of both elements on every face, at 11 points;
    // the functions without support on a face vanish there.
    double trace_difference = 0., off_face = 0.;
    for (const unsigned int f : GeometryInfo<2>::face_indices())
      for (unsigned int k = 0; k <= 10; ++k)
        {
          const double t = 0.1 * k;
          Point<2>     p;
          p[f / 2]     = f % 2;
          p[1 - f / 2] = t;
          std::vector<bool> on_face(8, false);
          for (unsigned int j = 0; j < q8.n_dofs_per_face(f); ++j)
            {
              const unsigned int i8 = q8.face_to_cell_index(j, f);
              on_face[i8]           = true;
              trace_difference =
                std::max(trace_difference,
                         std::abs(
                           q8.shape_value(i8, p) -
                           q9.shape_value(q9.face_to_cell_index(j, f), p)));
              CHECK_TRUE(q8.has_support_on_face(i8, f));
            }
          for (unsigned int i = 0; i < 8; ++i)
            if (!on_face[i])
              {
                off_face = std::max(off_face, std::abs(q8.shape_value(i, p)));
                if (k == 0)
                  CHECK_TRUE(!q8.has_support_on_face(i, f));
              }
        }
    CHECK_CLOSE_ABS(trace_difference, 0., 1e-14);
    CHECK_CLOSE_ABS(off_face, 0., 1e-14);

    // Prolongation: the nodal values of a quadratic on the parent give
    // those on each child (the space is invariant under the child maps).
    const Field    quadratic(Field::quadratic);
    Vector<double> parent_values(8), child_values(8);
    for (unsigned int i = 0; i < 8; ++i)
      parent_values(i) = quadratic.value(q8.get_unit_support_points()[i]);
    double prolongation_error = 0.;
    for (unsigned int c = 0; c < GeometryInfo<2>::max_children_per_cell; ++c)
      {
        q8.get_prolongation_matrix(c).vmult(child_values, parent_values);
        for (unsigned int i = 0; i < 8; ++i)
          prolongation_error = std::max(
            prolongation_error,
            std::abs(child_values(i) -
                     quadratic.value(GeometryInfo<2>::child_to_cell_coordinates(
                       q8.get_unit_support_points()[i],
                       c))));
      }
    CHECK_CLOSE_ABS(prolongation_error, 0., 1e-14);

    // Degree other than 2: refused.
    bool refused = false;
    try
      {
        FE_Serendipity<2> cubic(3);
      }
    catch (const std::exception &e)
      {
        refused = std::string(e.what()).find("degree 3") != std::string::npos;
      }
    CHECK_TRUE(refused);
  }

  void
  check_mass()
  {
    std::cout << "--- mass of one undistorted Q8 element" << std::endl;
    const Point<2> a(-1., 0.5), b(3., 1.5);
    const double   density = 2.7;
    BodyGeometry   geometry;
    geometry.shape              = BodyGeometry::Shape::rectangle;
    geometry.lower_left         = a;
    geometry.upper_right        = b;
    geometry.global_refinements = 0;
    const auto discretization =
      create_discretization<2>(DiscretizationMethod::fea,
                               geometry,
                               2,
                               FEAElement::serendipity);
    std::cout << "    " << discretization->name() << std::endl;
    CHECK_TRUE(discretization->name() ==
               "FEA, FESystem<2>[FE_Serendipity<2>(2)^2], MappingQ(2)");
    CHECK_TRUE(discretization->n_dofs() == 16);
    const double element_mass = density * (b[0] - a[0]) * (b[1] - a[1]);

    AffineConstraints<double> no_constraints;
    no_constraints.close();
    SparsityPattern sparsity;
    make_sparsity_pattern(*discretization, no_constraints, sparsity);
    SparseMatrix<double> consistent(sparsity);
    assemble_consistent_mass_matrix(*discretization,
                                    density,
                                    no_constraints,
                                    consistent);
    const Vector<double> hrz = assemble_lumped_mass(*discretization,
                                                    density,
                                                    MassScheme::hrz,
                                                    no_constraints);
    for (types::global_dof_index i = 0; i < discretization->n_dofs(); ++i)
      {
        const Point<2> x = discretization->dof_position(i);
        const bool     corner =
          (std::abs(x[0] - a[0]) < 1e-12 || std::abs(x[0] - b[0]) < 1e-12) &&
          (std::abs(x[1] - a[1]) < 1e-12 || std::abs(x[1] - b[1]) < 1e-12);
        const std::string where = std::string(corner ? "corner" : "mid-side") +
                                  " dof " + std::to_string(i);
        double row_sum = 0.;
        for (auto entry = consistent.begin(i); entry != consistent.end(i);
             ++entry)
          row_sum += entry->value();
        isoimpact_tests::check_close("consistent diagonal / m_e, " + where,
                                     consistent.diag_element(i) / element_mass,
                                     corner ? 1. / 30. : 8. / 45.,
                                     1e-13);
        isoimpact_tests::check_close("HRZ / m_e, " + where,
                                     hrz(i) / element_mass,
                                     corner ? 3. / 76. : 16. / 76.,
                                     1e-13);
        isoimpact_tests::check_close("row sum / m_e, " + where,
                                     row_sum / element_mass,
                                     corner ? -1. / 12. : 1. / 3.,
                                     1e-13);
      }
    CHECK_CLOSE(integrate_mass(*discretization, density), element_mass, 1e-13);

    // The project's row-sum lumping refuses the negative corner masses.
    std::string message;
    try
      {
        assemble_lumped_mass(*discretization,
                             density,
                             MassScheme::row_sum,
                             no_constraints);
      }
    catch (const std::exception &e)
      {
        message = e.what();
      }
    std::cout << "    row-sum refused with: " << message << std::endl;
    CHECK_TRUE(message.find("row-sum mass lumping gives the non-positive") !=
               std::string::npos);
    CHECK_TRUE(message.find("-0.0833333") != std::string::npos &&
               message.find("of the element mass") != std::string::npos);
  }

  void
  check_interpolation_and_output()
  {
    const FE_Serendipity<2> fe;
    const MappingQ<2>       mapping(2);
    Vector<double>          u;
    for (const bool affine : {true, false})
      {
        std::cout << "--- interpolation on a mesh of "
                  << (affine ? "parallelograms" : "trapezoids") << std::endl;
        Triangulation<2> tria;
        make_distorted_mesh(tria, affine);
        DoFHandler<2> dof_handler(tria);
        dof_handler.distribute_dofs(fe);
        CHECK_TRUE(dof_handler.n_dofs() == 16 + 24);
        const double quadratic_error =
          interpolation_error(dof_handler, mapping, Field(Field::quadratic), u);
        const double linear_error =
          interpolation_error(dof_handler, mapping, Field(Field::linear), u);
        const double x2y2_error =
          interpolation_error(dof_handler, mapping, Field(Field::x2y2), u);
        std::cout << "    relative L2 errors: quadratic " << quadratic_error
                  << ", linear " << linear_error << ", x^2 y^2 " << x2y2_error
                  << std::endl;
        CHECK_CLOSE_ABS(linear_error, 0., 1e-12);
        if (affine)
          {
            CHECK_CLOSE_ABS(quadratic_error, 0., 1e-12);
            CHECK_TRUE(x2y2_error > 1e-4);

            DataOut<2> data_out;
            data_out.attach_dof_handler(dof_handler);
            data_out.add_data_vector(u, "x2y2");
            data_out.build_patches(mapping, 2);
            std::ostringstream vtu;
            data_out.write_vtu(vtu);
            std::cout << "    VTU of " << vtu.str().size() << " bytes"
                      << std::endl;
            CHECK_TRUE(vtu.str().size() > 1000);
          }
        else
          CHECK_TRUE(quadratic_error > 1e-6);
      }
  }

  // Largest jump of u across the faces where a cell meets a coarser
  // neighbour, at 5 points of each such face.
  double
  hanging_face_jump(const DoFHandler<2>  &dof_handler,
                    const Mapping<2>     &mapping,
                    const Vector<double> &u)
  {
    const QGauss<1>     face_quadrature(5);
    FEFaceValues<2>     fine_values(mapping,
                                dof_handler.get_fe(),
                                face_quadrature,
                                update_values | update_quadrature_points);
    std::vector<double> fine(face_quadrature.size());
    double              jump = 0.;
    for (const auto &cell : dof_handler.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (!cell->at_boundary(f) && cell->neighbor_is_coarser(f))
          {
            fine_values.reinit(cell, f);
            fine_values.get_function_values(u, fine);
            const auto            coarse = cell->neighbor(f);
            std::vector<Point<2>> unit_points;
            for (const unsigned int q : fine_values.quadrature_point_indices())
              unit_points.push_back(mapping.transform_real_to_unit_cell(
                coarse,
                fine_values.quadrature_point(q)));
            FEValues<2>         coarse_values(mapping,
                                      dof_handler.get_fe(),
                                      Quadrature<2>(unit_points),
                                      update_values);
            std::vector<double> coarse_u(unit_points.size());
            coarse_values.reinit(coarse);
            coarse_values.get_function_values(u, coarse_u);
            for (unsigned int q = 0; q < unit_points.size(); ++q)
              jump = std::max(jump, std::abs(fine[q] - coarse_u[q]));
          }
    return jump;
  }

  void
  check_hanging_nodes()
  {
    std::cout << "--- hanging nodes" << std::endl;
    const FE_Serendipity<2> fe;
    const MappingQ<2>       mapping(2);
    Triangulation<2>        tria;
    make_distorted_mesh(tria, true);
    tria.begin_active()->set_refine_flag();
    tria.execute_coarsening_and_refinement();
    (++tria.begin_active(1))->set_refine_flag();
    tria.execute_coarsening_and_refinement();
    DoFHandler<2> dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    AffineConstraints<double> constraints;
    DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    constraints.close();
    std::cout << "    " << tria.n_active_cells() << " cells, "
              << dof_handler.n_dofs() << " dofs, "
              << constraints.n_constraints() << " hanging" << std::endl;
    CHECK_TRUE(constraints.n_constraints() > 0);

    Vector<double> u;
    CHECK_CLOSE_ABS(
      interpolation_error(dof_handler, mapping, Field(Field::quadratic), u),
      0.,
      1e-12);
    Vector<double> distributed = u;
    constraints.distribute(distributed);
    distributed -= u;
    CHECK_CLOSE_ABS(distributed.linfty_norm(), 0., 1e-12);
    CHECK_CLOSE_ABS(hanging_face_jump(dof_handler, mapping, u), 0., 1e-12);

    interpolation_error(dof_handler, mapping, Field(Field::x2y2), u);
    const double jump_before = hanging_face_jump(dof_handler, mapping, u);
    constraints.distribute(u);
    const double jump_after = hanging_face_jump(dof_handler, mapping, u);
    std::cout << "    x^2 y^2: jump before distribute " << jump_before
              << ", after " << jump_after << std::endl;
    CHECK_TRUE(jump_before > 1e-6);
    CHECK_CLOSE_ABS(jump_after, 0., 1e-12);
  }
} // namespace

int
main()
{
  check_element_against_fe_q();
  check_mass();
  check_interpolation_and_output();
  check_hanging_nodes();

  BodyGeometry rectangle;
  rectangle.shape              = BodyGeometry::Shape::rectangle;
  rectangle.lower_left         = Point<2>(-1., 0.5);
  rectangle.upper_right        = Point<2>(2., 2.);
  rectangle.global_refinements = 2;
  // Energies to 1e-12; residuals, strains, stresses and values to 1e-12 on
  // the rectangles, 1e-10 on the half disk.
  const auto check_q8_patch_test = [](const std::string  &name,
                                      const BodyGeometry &geometry,
                                      const double        field_tolerance) {
    isoimpact_tests::PatchTestOptions options;
    options.energy_tolerance = 1e-12;
    options.field_tolerance  = field_tolerance;
    isoimpact_tests::check_patch_test(
      name,
      create_discretization<2>(DiscretizationMethod::fea,
                               geometry,
                               2,
                               FEAElement::serendipity),
      true,
      options);
  };
  check_q8_patch_test("rectangle", rectangle, 1e-12);

  BodyGeometry rectangle_hanging      = rectangle;
  rectangle_hanging.local_refinements = 2;
  rectangle_hanging.refinement_center = Point<2>(-1., 0.5);
  rectangle_hanging.refinement_radius = 0.5;
  check_q8_patch_test("rectangle with hanging nodes", rectangle_hanging, 1e-12);

  const BodyGeometry half_disk = isoimpact_tests::half_disk(2);
  check_q8_patch_test("half disk", half_disk, 1e-10);

  // Contact segments of the arc: as many as with FE_Q(2), three nodes each,
  // and the segment curve passes through its nodes at eta = 0, 1/2, 1
  // (nodal trace), to round-off relative to R = 4.
  {
    std::cout << "--- boundary segments of the half disk" << std::endl;
    const auto q8 = create_discretization<2>(DiscretizationMethod::fea,
                                             half_disk,
                                             2,
                                             FEAElement::serendipity);
    const auto q9 =
      create_discretization<2>(DiscretizationMethod::fea, half_disk, 2);
    const auto segments = q8->boundary_segments(0);
    CHECK_TRUE(segments.size() == q9->boundary_segments(0).size());
    double              node_distance = 0.;
    bool                three_nodes   = true;
    std::vector<double> r, dr;
    for (const auto &segment : segments)
      {
        three_nodes = three_nodes && segment.node_positions.size() == 3;
        for (const double eta : {0., 0.5, 1.})
          {
            evaluate_segment_basis(segment, eta, r, dr);
            Point<2> x;
            for (unsigned int k = 0; k < r.size(); ++k)
              x += r[k] * segment.node_positions[k];
            double nearest = 1e300;
            for (const auto &node : segment.node_positions)
              nearest = std::min(nearest, x.distance(node));
            node_distance = std::max(node_distance, nearest);
          }
      }
    CHECK_TRUE(three_nodes);
    CHECK_CLOSE_ABS(node_distance, 0., 1e-13);
  }

  // The factory refuses Q8 for other degrees and for IGA.
  for (const auto &[kind, degree] : {std::make_pair(std::string("fea"), 3u),
                                     std::make_pair(std::string("iga"), 2u)})
    {
      std::string message;
      try
        {
          create_discretization<2>(discretization_method_names.from_string(
                                     kind),
                                   rectangle,
                                   degree,
                                   FEAElement::serendipity);
        }
      catch (const std::exception &e)
        {
          message = e.what();
        }
      std::cout << "    " << kind << ", degree " << degree
                << ": refused with: " << message << std::endl;
      CHECK_TRUE(message.find("serendipity") != std::string::npos);
    }
  return isoimpact_tests::report();
}
