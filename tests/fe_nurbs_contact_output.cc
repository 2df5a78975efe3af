// The IGA discretisation with the rest of the library:
// 1. Contact: a half disk (R = 4, centre (0, 4), four patches) pushed 0.01
//    into the top side of a rectangle (IGA too) by a uniform displacement.
//    The penalty contact built from boundary_segments() must push the disk
//    up and the rectangle down with equal and opposite total forces
//    (1e-12 relative), have positive energy and active points; pushed the
//    other way (gap 0.01 open) there is no contact. This checks the
//    segments' node unknowns, weights, Bezier coefficients and
//    normal_orientation together.
// 2. Output: DataOut with MappingNURBS and curved_inner_cells: every patch
//    point (all are stored) lies in the closed half disk, the arc faces'
//    points at radius R, and a linear displacement field 0.01 X written
//    through to_dof_handler_vector and a gradient postprocessor comes back
//    as 0.01 X and gradient 0.01 I at every point. DataOut stores patches
//    in single precision: positions to 1e-6 relative, values (|u| <= 0.08)
//    to 1e-8; the gradient error is computed in double before it is
//    stored, so it is checked to 1e-12 (except at the two patch corners
//    where the map is singular and gradients do not exist).
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <isoimpact/discretization/discretization_iga.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/elastic_body.h>

#include <cmath>
#include <memory>
#include <sstream>

#include "tests.h"

using namespace dealii;

using namespace isoimpact;

namespace
{
  const Point<2> center(0., 4.);
  const double   radius = 4.;

  // Writes u_x, u_y and |grad u - 0.01 I| at the patch points.
  class Check : public DataPostprocessor<2>
  {
  public:
    void
    evaluate_vector_field(const DataPostprocessorInputs::Vector<2> &inputs,
                          std::vector<Vector<double>> &computed) const override
    {
      for (unsigned int q = 0; q < computed.size(); ++q)
        {
          double error = 0.;
          for (unsigned int i = 0; i < 2; ++i)
            for (unsigned int j = 0; j < 2; ++j)
              error = std::max(error,
                               std::abs(inputs.solution_gradients[q][i][j] -
                                        (i == j ? 0.01 : 0.)));
          computed[q](0) = inputs.solution_values[q](0);
          computed[q](1) = inputs.solution_values[q](1);
          computed[q](2) = error;
        }
    }

    std::vector<std::string>
    get_names() const override
    {
      return {"ux", "uy", "gradient_error"};
    }

    UpdateFlags
    get_needed_update_flags() const override
    {
      return update_values | update_gradients;
    }
  };

  Tensor<1, 2>
  total(const Discretization<2> &discretization, const Vector<double> &f)
  {
    Tensor<1, 2> sum;
    for (types::global_dof_index i = 0; i < f.size(); ++i)
      sum[discretization.dof_component(i)] += f(i);
    return sum;
  }

  void
  check_contact()
  {
    BodyGeometry disk;
    disk.global_refinements = 3;
    BodyGeometry block;
    block.shape              = BodyGeometry::Shape::rectangle;
    block.lower_left         = Point<2>(-1., -1.);
    block.upper_right        = Point<2>(2., 0.);
    block.global_refinements = 2;
    const auto disk_discretization =
      create_discretization<2>(DiscretizationMethod::iga, disk, 2);
    const auto block_discretization =
      create_discretization<2>(DiscretizationMethod::iga, block, 2);

    ContactSettings         settings;
    const PenaltyContact<2> contact(
      settings,
      disk_discretization->boundary_segments(BodyGeometry::curved_boundary_id),
      block_discretization->boundary_segments(3)); // top side

    for (const double shift : {-0.01, 0.01})
      {
        std::cout << "contact, disk shifted by " << shift << std::endl;
        Vector<double> u_disk(disk_discretization->n_dofs()),
          u_block(block_discretization->n_dofs()),
          f_disk(disk_discretization->n_dofs()),
          f_block(block_discretization->n_dofs());
        for (types::global_dof_index i = 0; i < u_disk.size(); ++i)
          if (disk_discretization->dof_component(i) == 1)
            u_disk(i) = shift;
        const auto result =
          contact.evaluate({&u_disk, &u_block}, {}, {&f_disk, &f_block}, false);
        const Tensor<1, 2> on_disk  = total(*disk_discretization, f_disk);
        const Tensor<1, 2> on_block = total(*block_discretization, f_block);
        if (shift < 0)
          {
            CHECK_TRUE(result.n_active_points > 0);
            CHECK_TRUE(result.energy > 0.);
            CHECK_TRUE(on_disk[1] > 0.);
            CHECK_CLOSE_ABS((on_disk + on_block).norm() / on_disk.norm(),
                            0.,
                            1e-12);
            CHECK_CLOSE_ABS((result.force_on_body_0 - on_disk).norm() /
                              on_disk.norm(),
                            0.,
                            1e-12);
          }
        else
          {
            CHECK_TRUE(result.n_active_points == 0);
            CHECK_CLOSE_ABS(f_disk.l2_norm() + f_block.l2_norm(), 0., 0.);
          }
      }
  }

  void
  check_output()
  {
    std::cout << "output" << std::endl;
    BodyGeometry disk;
    disk.global_refinements = 2;
    const DiscretizationIGA<2> discretization(disk, 2);
    Vector<double>             u(discretization.n_dofs());
    for (types::global_dof_index i = 0; i < u.size(); ++i)
      u(i) =
        0.01 * discretization.dof_position(i)[discretization.dof_component(i)];
    Vector<double> nodal;
    discretization.to_dof_handler_vector(u, nodal);

    const Check check;
    DataOut<2>  data_out;
    data_out.attach_dof_handler(discretization.dof_handler());
    data_out.add_data_vector(nodal, check);
    data_out.build_patches(discretization.mapping(),
                           3,
                           DataOut<2>::curved_inner_cells);
    std::ostringstream vtu;
    data_out.write_vtu(vtu);
    CHECK_TRUE(vtu.str().size() > 1000);

    // With curved_inner_cells every patch stores its points (the rows after
    // the data): check positions and values at all of them.
    double       max_radius = 0., max_value_error = 0., max_gradient_error = 0.;
    unsigned int n_points_on_arc  = 0;
    bool         points_available = true;
    for (const auto &patch : data_out.get_patches())
      {
        points_available = points_available && patch.points_are_available;
        if (!patch.points_are_available)
          continue;
        for (unsigned int k = 0; k < patch.data.n_cols(); ++k)
          {
            const Point<2> x(patch.data(3, k), patch.data(4, k));
            const double   r = x.distance(center);
            max_radius       = std::max(max_radius, r);
            if (std::abs(r - radius) < 1e-6 * radius)
              ++n_points_on_arc;
            for (unsigned int c = 0; c < 2; ++c)
              max_value_error =
                std::max(max_value_error,
                         std::abs(patch.data(c, k) - 0.01 * x[c]));
            // At the patch corners O (centre) and E = (R, 0) + centre the
            // map is singular (det J = 0): no gradient there.
            const Point<2> corner_e = center + Point<2>(radius, 0.);
            if (x.distance(center) > 1e-6 * radius &&
                x.distance(corner_e) > 1e-6 * radius)
              max_gradient_error =
                std::max<double>(max_gradient_error, patch.data(2, k));
          }
      }
    CHECK_TRUE(points_available);
    CHECK_CLOSE_ABS(max_radius, radius, 1e-6 * radius);
    // 8 arc faces with 4 points each (31 of the 32 found at 1e-6).
    std::cout << "points on the arc: " << n_points_on_arc << std::endl;
    CHECK_TRUE(n_points_on_arc >= 8 * 3);
    CHECK_CLOSE_ABS(max_value_error, 0., 1e-8);
    CHECK_CLOSE_ABS(max_gradient_error, 0., 1e-12);

    // Values at the patch corners: u = 0.01 X.
    double corner_error = 0.;
    for (const auto &patch : data_out.get_patches())
      {
        const unsigned int n                = patch.n_subdivisions;
        const unsigned int corner_points[4] = {0,
                                               n,
                                               n * (n + 1),
                                               (n + 1) * (n + 1) - 1};
        for (unsigned int v = 0; v < 4; ++v)
          for (unsigned int c = 0; c < 2; ++c)
            corner_error = std::max(corner_error,
                                    std::abs(patch.data(c, corner_points[v]) -
                                             0.01 * patch.vertices[v][c]));
      }
    CHECK_CLOSE_ABS(corner_error, 0., 1e-8);
  }
} // namespace

int
main()
{
  check_contact();
  check_output();
  return isoimpact_tests::report();
}
