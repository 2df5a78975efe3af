// Ready-made NURBS patches with exact circular boundaries, and a small text
// format for user patches (layer 1).
#ifndef isoimpact_nurbs_geometries_h
#define isoimpact_nurbs_geometries_h

#include <deal.II/base/point.h>

#include <isoimpact/nurbs/enum_names.h>
#include <isoimpact/nurbs/patch.h>

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

namespace isoimpact
{
  namespace nurbs
  {
    // What a patch side is, for the contact and symmetry code.
    enum class SideKind
    {
      unspecified, // not known (user patch without side lines); the default
      arc,         // exactly circular boundary (potential contact surface)
      symmetry,    // straight cut on a symmetry line
      straight     // other straight boundary
    };

    // "arc", "symmetry", "straight", "unspecified", as in patch files.
    inline constexpr EnumNames<SideKind, 4> side_kind_names{
      "side kind",
      {{{SideKind::arc, "arc"},
        {SideKind::symmetry, "symmetry"},
        {SideKind::straight, "straight"},
        {SideKind::unspecified, "unspecified"}}}};

    inline std::string
    to_string(const SideKind kind)
    {
      return side_kind_names.to_string(kind);
    }

    /**
     * A patch with the meaning of its sides. Sides (faces) are numbered
     * f = 2 * direction + side, side 0 at the lower and 1 at the upper end
     * of the parametric direction, as deal.II numbers the unit cell faces.
     * Refinement of `patch` keeps the parametrization, so the sides and the
     * contact parameter stay valid.
     */
    template <int dim, int spacedim = dim>
    struct PatchGeometry
    {
      NURBSPatch<dim, spacedim>     patch;
      std::array<SideKind, 2 * dim> side_kinds{};
      // Whether the body has a designated first contact point, a patch corner.
      bool                    has_contact_point = false;
      dealii::Point<dim>      contact_parameter;
      dealii::Point<spacedim> contact_point;

      // The faces of the given kind, increasing.
      std::vector<unsigned int>
      sides_of_kind(const SideKind kind) const;
    };

    /**
     * Side numbers of half_disk(). Parametric corners (xi_0, xi_1):
     * (0,0) = contact point C = (cx, cy - R), (1,0) = E = (cx + R, cy),
     * (1,1) = T = (cx, cy + R), (0,1) = O = centre (cx, cy).
     */
    namespace half_disk_sides
    {
      // xi_0 = 0: lower half of the cut, from C (xi_1 = 0) to O (xi_1 = 1).
      constexpr unsigned int lower_symmetry = 0;
      // xi_0 = 1: upper quarter arc, from E (xi_1 = 0) to T (xi_1 = 1).
      constexpr unsigned int upper_arc = 1;
      // xi_1 = 0: lower quarter arc, from C (xi_0 = 0) to E (xi_0 = 1).
      constexpr unsigned int lower_arc = 2;
      // xi_1 = 1: upper half of the cut, from O (xi_0 = 0) to T (xi_0 = 1).
      constexpr unsigned int upper_symmetry = 3;
      // The contact point is the patch vertex xi = (0, 0) (deal.II vertex 0),
      // where lower_symmetry and lower_arc meet at a right angle.
      constexpr unsigned int contact_vertex = 0;
    } // namespace half_disk_sides

    /**
     * THE benchmark body: the half of the disk of given centre and radius
     * with x >= center[0]. One biquadratic NURBS element whose four sides
     * are the lower and upper quarter arcs and the two halves of the
     * diameter (see half_disk_sides). The arc sides are exact circles. det J
     * > 0 in the whole patch except at the two corners E and O, where the
     * boundary is straight (180 degree angle) and J has rank 1; the contact
     * corner C is a regular right-angle corner. Refine with the NURBSPatch
     * functions (e.g. refine_graded(0, 0, ...) and refine_graded(1, 0, ...)
     * toward the contact point).
     */
    PatchGeometry<2>
    half_disk(const double radius, const dealii::Point<2> &center = {});

    /**
     * The full disk: one biquadratic element, corners at 45 degree points
     * (det J = 0 only at the four corners), all four sides arcs: side 0
     * left, 1 right, 2 bottom, 3 top quarter arc. No contact point.
     */
    PatchGeometry<2>
    full_disk(const double radius, const dealii::Point<2> &center = {});

    /**
     * Quarter annulus in the first quadrant around center. Direction 0 runs
     * radially (inner to outer radius), direction 1 along the angle (0 to 90
     * degrees), quadratic in both. Sides: 0 inner arc, 1 outer arc, 2 (angle
     * 0, on the x axis) and 3 (angle 90, on the y axis) symmetry.
     */
    PatchGeometry<2>
    quarter_annulus(const double            inner_radius,
                    const double            outer_radius,
                    const dealii::Point<2> &center = {});

    /**
     * The axis-parallel rectangle with opposite corners corner1, corner2, one
     * element of the given degree in both directions, affine map (direction
     * 0 along x, 1 along y). All sides straight.
     */
    PatchGeometry<2>
    rectangle(const dealii::Point<2> &corner1,
              const dealii::Point<2> &corner2,
              const unsigned int      degree = 2);

    /**
     * One biquadratic element on a quadrilateral given by its vertices in
     * deal.II order (parametric corners (0,0), (1,0), (0,1), (1,1)). A side
     * of kind `arc` is the circular arc around `arc_center` between its two
     * end vertices (they must be equidistant from it, the arc shorter than
     * a half circle); every other side is straight, at constant speed. The
     * interior control point blends the sides bilinearly (Coons) in
     * homogeneous coordinates, so a patch with one arc side is the ruled
     * surface between it and the opposite side, and its straight sides have
     * weights 1: patches built this way on a conforming mesh glue C0.
     */
    PatchGeometry<2>
    quadrilateral(const std::array<dealii::Point<2>, 4> &vertices,
                  const std::array<SideKind, 4>         &side_kinds,
                  const dealii::Point<2>                &arc_center = {});

    /**
     * Reads a patch from a text file. Format ('#' starts a comment, blank
     * lines are ignored, keywords in this order):
     *
     *   dimension 2 2               # dim spacedim
     *   degrees 2 2                 # one degree per direction
     *   knots 0 0 0 1 1 1           # one line per direction, in order
     *   knots 0 0 0 0.5 1 1 1
     *   control_points 12           # count, then that many lines:
     *   0 -1 1                      #   x y [z] weight, first direction fastest
     *   ...
     *   side 0 symmetry             # optional, per side: arc | symmetry |
     *   side 2 arc                  #   straight (default unspecified)
     *   contact 0 0                 # optional: parameter point of the contact
     *
     * Errors throw an exception naming the file, the line and the problem;
     * dim and spacedim must match the template arguments.
     */
    template <int dim, int spacedim = dim>
    PatchGeometry<dim, spacedim>
    read_patch(const std::string &filename);

    // Writes a patch in the format read by read_patch (full precision).
    template <int dim, int spacedim>
    void
    write_patch(const PatchGeometry<dim, spacedim> &geometry,
                std::ostream                       &out);

    template <int dim, int spacedim>
    void
    write_patch(const PatchGeometry<dim, spacedim> &geometry,
                const std::string                  &filename);
  } // namespace nurbs
} // namespace isoimpact

#endif
