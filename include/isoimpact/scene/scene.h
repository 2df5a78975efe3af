// Layer 6: a scene built from parameters: the bodies, their contact (two
// bodies, or Body 1 against a rigid obstacle) and the analytic reference.
#ifndef isoimpact_scene_h
#define isoimpact_scene_h

#include <isoimpact/mechanics/rigid_obstacle.h>
#include <isoimpact/scene/hertz_reference.h>
#include <isoimpact/scene/parameters.h>
#include <isoimpact/time_integration/central_difference.h>
#include <isoimpact/time_integration/stability_monitor.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace isoimpact
{
  struct Scene
  {
    std::vector<std::unique_ptr<ElasticBody<2>>>  bodies;
    std::vector<std::unique_ptr<ContactModel<2>>> contacts;
    std::vector<ContactInteraction<2>>            interactions;
    // The declared contact surface of every body (its arcs).
    std::vector<std::vector<BoundarySegment<2>>> contact_surfaces;

    // Contact force and energies are reported for the full physical
    // bodies: the modelled ones times this factor.
    double symmetry_factor = 1.;
    // Several MPI ranks: body b whole on rank b (Parallel/Distribution),
    // else every body split over all ranks.
    bool bodies_on_ranks = false;
    // Unit vector along the relative initial velocity of the two bodies (of
    // the fixed obstacle and body 1): the contact force reported is the
    // resultant on body 1 along it.
    dealii::Tensor<1, 2> impact_direction;
    // The quasi-static Hertz impact, if the parameters ask for it. Against
    // a rigid plane: the impact of body 1 and its mirror image at twice the
    // normal speed (the same force history); against a rigid cylinder: the
    // rigid limit (modulus and density 1e12 times body 1's).
    std::unique_ptr<HertzImpactReference> reference;

    std::vector<ElasticBody<2> *>
    body_pointers() const;

    dealii::types::global_dof_index
    n_dofs() const;
  };

  // Throws InputError (or deal.II's exceptions for inadmissible lumping).
  Scene
  build_scene(const Parameters &parameters);

  /**
   * The checks of a scene that need more than one parameter at a time, done
   * before anything is built (throw InputError naming the file, the
   * parameters, their values and what is allowed):
   * - the bodies do not overlap at t = 0 (they may touch), Body 1 does not
   *   start inside a rigid plane or cylinder, nor the cylinder inside it;
   * - with an analytic reference, the bodies (Body 1 and the plane or
   *   cylinder) touch at t = 0 and close along the line of centres, and the
   *   reference can describe the impact (closing speed below its limit);
   * - the estimated memory of the meshes and matrices, counted whole on
   *   each of n_ranks MPI ranks, fits in the available memory (MemAvailable
   *   of /proc/meminfo);
   * - a given time step gives at most max_time_steps steps.
   */
  void
  check_scene(const Parameters  &parameters,
              const std::string &parameter_file,
              const unsigned int n_ranks = 1);

  // The estimated peak memory of a run, bytes, and its cells (all bodies).
  std::pair<double, double>
  estimated_memory_and_cells(const Parameters &parameters);

  // The most steps a run may take.
  constexpr double max_time_steps = 1e8;

  // The steps of a run and the step that ends them exactly at End time: the
  // selected step is shortened to End time / n, n = ceil(End time / step)
  // (kept as it is if that differs from it by round-off only).
  struct TimeSteps
  {
    std::uint64_t n_steps;
    double        time_step;
  };

  // Throws InputError if more than max_time_steps steps are needed.
  TimeSteps
  time_steps_to_end(const Parameters  &parameters,
                    const double       selected_time_step,
                    const std::string &parameter_file);

  /**
   * How many faces of body 1's contact surface span the contact width 2a of
   * the analytic reference at its peak force: 2a over the length of the
   * face nearest to the first point of contact. 0 without a reference.
   */
  double
  faces_across_contact_zone(const Scene &scene, const Parameters &parameters);

  // Below this many faces across the contact width the contact force peaks
  // are several percent off (the refinement study: doc/stability.md).
  constexpr double recommended_faces_across_contact_zone = 8.;

  /**
   * The time step of the run: with Time step = auto the safety factor times
   * the guaranteed bound `stable`; a given step above the bound throws an
   * InputError naming both (unless the parameters allow it).
   */
  double
  select_time_step(const Parameters     &parameters,
                   const StableTimeStep &stable,
                   const std::string    &parameter_file);
} // namespace isoimpact

#endif
