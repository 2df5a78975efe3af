// Layer 4: symmetric two-pass penalty contact between two deformable
// bodies (frictionless, 2D), on the boundary segments of layer 3.
//
// Virtual work: delta Pi_c = sum over the two passes of
//   eps_pass * integral over the slave surface of g_N delta g_N, g_N < 0,
// where a pass takes one surface as slave (its Gauss points) and projects
// onto the other (master). Convention (`PenaltyPerPass`):
//   half: eps_pass = eps_N / 2, so that the two passes together act like a
//         single-pass penalty eps_N (pressure ~ eps_N |g_N|), the default;
//   full: eps_pass = eps_N, the formulation written with eps_N on both
//         boundaries (effective penalty 2 eps_N).
#ifndef isoimpact_contact_h
#define isoimpact_contact_h

#include <deal.II/base/tensor.h>

#include <isoimpact/discretization.h>

#include <memory>
#include <string>
#include <vector>

namespace isoimpact
{
  enum class PenaltyPerPass
  {
    half,
    full
  };

  PenaltyPerPass
  penalty_per_pass_from_string(const std::string &name);

  struct ContactSettings
  {
    double         penalty             = 1e5; // eps_N, Pa/m
    PenaltyPerPass penalty_per_pass    = PenaltyPerPass::half;
    unsigned int   n_quadrature_points = 4; // Gauss points per segment
  };

  // One point of a contact surface where the penalty is active.
  template <int dim>
  struct ContactPoint
  {
    Point<dim>   reference_position; // on the slave surface
    double       pressure;           // eps_N,effective * |g_N|, Pa
    double       gap;                // g_N, m (negative)
    unsigned int slave_surface;      // 0 or 1
  };

  template <int dim>
  struct ContactResult
  {
    double                         energy = 0.; // J/m (per unit thickness)
    double                         max_pressure = 0.;      // Pa
    Tensor<1, dim>                 force_on_first_surface; // N/m, resultant
    unsigned int                   n_active_points = 0;
    std::vector<ContactPoint<dim>> points;
  };

  template <int dim>
  class PenaltyContact
  {
  public:
    PenaltyContact(const ContactSettings            &settings,
                   std::vector<BoundarySegment<dim>> first_surface,
                   std::vector<BoundarySegment<dim>> second_surface);
    ~PenaltyContact();

    // Adds the contact forces for displacements u (in each body's unknowns)
    // to the force vectors f; returns energy, pressure and resultant.
    ContactResult<dim>
    add_forces(const Vector<double> &u_first,
               const Vector<double> &u_second,
               Vector<double>       &f_first,
               Vector<double>       &f_second,
               const bool            record_points = false) const;

    double
    penalty_per_pass() const;

    // Number of Gauss points on each surface (slaves of the two passes).
    unsigned int
    n_slave_points() const;

  private:
    struct Surface;
    ContactSettings                         settings;
    std::array<std::unique_ptr<Surface>, 2> surfaces;
  };
} // namespace isoimpact

#endif
