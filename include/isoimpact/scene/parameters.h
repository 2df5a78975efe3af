// Layer 6: the parameters of a scene, read from a .prm file with deal.II's
// ParameterHandler (step-44 style: one struct per subsection).
#ifndef isoimpact_parameters_h
#define isoimpact_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <isoimpact/discretization/discretization.h>
#include <isoimpact/discretization/unknown_exchange.h>
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/mechanics/material.h>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace isoimpact
{
  // A bad input: the message names the file, the parameter, the value and
  // what is allowed.
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  struct BodyParameters
  {
    BodyGeometry         geometry;
    ElasticMaterial      material;
    dealii::Tensor<1, 2> initial_velocity;
    bool                 symmetry_cut = true;
  };

  // A rigid, fixed, frictionless obstacle (subsection Obstacle). With a
  // type other than none the scene is Body 1 against the obstacle and
  // Body 2 is ignored.
  struct ObstacleParameters
  {
    std::string          type = "none"; // none, plane, cylinder, channel
    dealii::Point<2>     point;         // plane
    dealii::Tensor<1, 2> normal;        // plane, out of the obstacle
    dealii::Point<2>     opposite_point = dealii::Point<2>(0., 10.); // channel
    dealii::Point<2>     center         = dealii::Point<2>(0., -4.); // cylinder
    double               radius         = 4.;                        // cylinder
    double               penalty        = 2e5;                       // Pa/m

    bool
    active() const
    {
      return type != "none";
    }
  };

  struct Parameters
  {
    std::array<BodyParameters, 2> bodies;
    ObstacleParameters            obstacle;

    // The deformable bodies of the scene: 1 with an obstacle, else 2.
    unsigned int
    n_bodies() const
    {
      return obstacle.active() ? 1 : 2;
    }

    // Discretization
    DiscretizationMethod method      = DiscretizationMethod::fea;
    FEAElement           fea_element = FEAElement::lagrange;
    unsigned int         degree      = 2;

    MassScheme mass_scheme = MassScheme::hrz;
    // Parallel/Load balancing (2 MPI ranks).
    LoadBalancing load_balancing = LoadBalancing::automatic;
    // Parallel/Distribution: automatic (bodies whole on ranks where that
    // balances, scene.cc) or every body split over all ranks.
    bool split_every_body = false;
    // Parallel/Thread partition = by body: each body's pass one task (its
    // rows on one thread), else in blocks the threads take as they come.
    bool pass_of_body_on_one_thread = false;
    // Parallel/Contact point exchange: how ranks that share the contact's
    // Gauss points exchange the projections' outcomes.
    PointExchange   contact_point_exchange = PointExchange::automatic;
    ContactSettings contact;
    // Penalty = auto (Contact/Penalty, and Obstacle/Penalty for an
    // obstacle): k = penalty_scale_factor mu / dt^2 (scene.cc).
    bool   automatic_penalty    = false;
    double penalty_scale_factor = 0.5;
    // Contact/Bipenalty: a mass penalty eps_m = bipenalty_mass_scale_factor
    // x the critical one, which keeps the stable step of the bodies without
    // contact (scene.cc, doc/formulation.md).
    bool   bipenalty                   = false;
    double bipenalty_mass_scale_factor = 1.;
    // Contact/Bipenalty switching: momentum (true) or velocity.
    bool bipenalty_momentum_switching = true;
    // Contact/Mass redistribution: massless contact surfaces solved
    // quasi-statically (mechanics/mass_redistribution.h,
    // time_integration/quasi_static_boundary.h).
    bool mass_redistribution = false;

    // Time integration. With automatic_time_step the step is the safety
    // factor times the guaranteed stable step bound with contact
    // (mechanics/stable_time_step.h); a given step above that bound is
    // refused unless allowed. The bound counts the contact springs
    // contact_activation_margin times (time_integration/stability_monitor.h).
    // The run stops when the total energy exceeds the input energy by
    // energy_growth_tolerance (a fraction of it) or a penetration exceeds
    // maximum_penetration (a fraction of the smallest body size).
    bool   automatic_time_step         = true;
    double time_step                   = 5e-4;
    double time_step_safety_factor     = 0.9;
    double contact_activation_margin   = 2.;
    bool   allow_time_step_above_bound = false;
    double end_time                    = 0.9;
    double energy_growth_tolerance     = 0.1;
    double maximum_penetration         = 0.25;

    // Output
    std::string         output_directory = "output/hertz";
    unsigned int        history_interval = 1;
    unsigned int        vtu_interval     = 100;
    unsigned int        vtu_subdivisions = 2;
    bool                vtu_higher_order = true; // VTU cells = higher order
    bool                vtu_compression  = false;
    std::vector<double> profile_times;
    std::string         approach_law      = "Gerl-Zippelius";
    double              progress_interval = 10.;   // percent of the run
    double              filter_window     = 0.01;  // s
    bool                step_times        = false; // step_times.csv

    // A scene whose deformable bodies (n_bodies()) are all half disks with
    // a symmetry cut models a half by symmetry: 2, else 1.
    double
    symmetry_factor() const;

    // The smallest size of the deformable bodies, m: a radius, or half the
    // shorter side of a rectangle (scale of Maximum penetration).
    double
    smallest_body_size() const;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);
  };

  // Reads and checks a parameter file; throws InputError.
  Parameters
  read_parameters(const std::string &filename);

  // A complete default file with the documentation of every parameter.
  void
  print_default_parameters(std::ostream &out);
} // namespace isoimpact

#endif
