// Layer 6: a scene built from parameters: the bodies, their contact (two
// bodies, or Body 1 against a rigid obstacle) and the analytic reference.
#ifndef isoimpact_scene_h
#define isoimpact_scene_h

#include <isoimpact/mechanics/rigid_obstacle.h>
#include <isoimpact/scene/hertz_reference.h>
#include <isoimpact/scene/parameters.h>
#include <isoimpact/time_integration/central_difference.h>
#include <isoimpact/time_integration/stability_monitor.h>

#include <memory>
#include <vector>

namespace isoimpact
{
  struct Scene
  {
    std::vector<std::unique_ptr<ElasticBody<2>>>  bodies;
    std::vector<std::unique_ptr<ContactModel<2>>> contacts;
    std::vector<ContactInteraction<2>>            interactions;

    // Contact force and energies are reported for the full physical
    // bodies: the modelled ones times this factor.
    double symmetry_factor = 1.;
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
