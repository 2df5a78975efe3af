// Layer 6: parameters.
#include <deal.II/base/exceptions.h>

#include <isoimpact/scene/hertz_reference.h>
#include <isoimpact/scene/parameters.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  namespace
  {
    const char *body_names[2] = {"Body 1", "Body 2"};

    // A positive number or the word auto (Time integration/Time step).
    class PositiveNumberOrAuto : public Patterns::PatternBase
    {
    public:
      bool
      match(const std::string &text) const override
      {
        return text == "auto" || Patterns::Double(0.).match(text);
      }
      std::string
      description(const OutputStyle) const override
      {
        return "[a floating point number >= 0 or auto]";
      }
      std::unique_ptr<PatternBase>
      clone() const override
      {
        return std::make_unique<PositiveNumberOrAuto>();
      }
    };

    std::string
    point_string(const Point<2> &p)
    {
      std::ostringstream s;
      s << p[0] << ", " << p[1];
      return s.str();
    }

    std::vector<double>
    parse_doubles(const std::string &text)
    {
      return Utilities::string_to_double(
        Utilities::split_string_list(text, ','));
    }

    // What ParameterHandler accepts silently: a file that sets nothing
    // (the default scene would run) and a key set twice (the last value
    // would win). The file is read as deal.II does: '#' starts a comment, a
    // trailing backslash continues the line.
    void
    check_file_structure(const std::string &filename)
    {
      std::ifstream            in(filename);
      std::vector<std::string> path;
      // "Subsection/.../Key" -> the line number and value of its first set.
      std::map<std::string, std::pair<unsigned int, std::string>> first_set;
      std::string                                                 line, text;
      unsigned int line_number = 0, first_line = 0;
      const auto   trim = [](const std::string &s) {
        std::string out;
        for (const char c : s) // collapse runs of white space
          if (!std::isspace(static_cast<unsigned char>(c)))
            out += c;
          else if (!out.empty() && out.back() != ' ')
            out += ' ';
        if (!out.empty() && out.back() == ' ')
          out.pop_back();
        return out;
      };
      while (std::getline(in, line))
        {
          ++line_number;
          if (text.empty())
            first_line = line_number;
          line                    = line.substr(0, line.find('#'));
          const std::string piece = trim(line);
          if (!piece.empty() && piece.back() == '\\')
            {
              text += piece.substr(0, piece.size() - 1) + ' ';
              continue;
            }
          text = trim(text + piece);
          if (text.rfind("subsection ", 0) == 0)
            path.push_back(text.substr(11));
          else if (text == "end" && !path.empty())
            path.pop_back();
          else if (text.rfind("set ", 0) == 0 &&
                   text.find('=') != std::string::npos)
            {
              const auto  equal = text.find('=');
              std::string key;
              for (const auto &name : path)
                key += name + "/";
              key += trim(text.substr(4, equal - 4));
              const std::string value = trim(text.substr(equal + 1));
              const auto [entry, inserted] =
                first_set.emplace(key, std::make_pair(first_line, value));
              if (!inserted)
                throw InputError(
                  "in parameter file '" + filename + "': parameter '" + key +
                  "' is set twice, on line " +
                  std::to_string(entry->second.first) + " (value '" +
                  entry->second.second + "') and on line " +
                  std::to_string(first_line) + " (value '" + value +
                  "'); each parameter may be set once: remove one");
            }
          text.clear();
        }
      if (first_set.empty())
        throw InputError(
          "in parameter file '" + filename +
          "': the file sets no parameter (it is empty or holds only "
          "comments), so the default scene would run; a complete file with "
          "every parameter: isoimpact --print-parameters");
    }

    void
    declare_body(ParameterHandler &prm, const unsigned int b)
    {
      prm.enter_subsection(body_names[b]);
      prm.declare_entry("Shape",
                        "half disk",
                        Patterns::Selection("half disk|full disk|rectangle"),
                        "Shape of the body. A half disk is cut along the "
                        "vertical line through its centre and keeps x >= "
                        "centre x; boundary 0 is its arc, 1 its cut. A "
                        "rectangle has boundaries 0, 1, 2, 3 = left, right, "
                        "bottom, top.");
      prm.declare_entry("Center",
                        b == 0 ? "0, 4" : "0, -4",
                        Patterns::List(Patterns::Double(), 2, 2),
                        "Centre of a disk or half disk, m.");
      prm.declare_entry("Radius",
                        "4",
                        Patterns::Double(0.),
                        "Radius of a disk or half disk, m (> 0).");
      prm.declare_entry("Lower left corner",
                        "0, 0",
                        Patterns::List(Patterns::Double(), 2, 2),
                        "Rectangle: lower left corner, m.");
      prm.declare_entry("Upper right corner",
                        "1, 1",
                        Patterns::List(Patterns::Double(), 2, 2),
                        "Rectangle: upper right corner, m.");
      prm.declare_entry("Initial velocity",
                        b == 0 ? "0, -2" : "0, 2",
                        Patterns::List(Patterns::Double(), 2, 2),
                        "Uniform initial velocity, m/s.");
      prm.declare_entry("Symmetry cut",
                        "true",
                        Patterns::Bool(),
                        "Half disk: the cut is a symmetry line (roller, "
                        "u_x = 0). A scene whose bodies are all cut models "
                        "half of the physical problem: contact force and "
                        "energies are reported for the full bodies.");
      prm.enter_subsection("Material");
      prm.declare_entry("Young's modulus",
                        "1000",
                        Patterns::Double(0.),
                        "E, Pa (> 0). The Hertz benchmark uses E = 1000 Pa: "
                        "with rho = 1 kg/m^3 the wave speed is 33 m/s and "
                        "the impact lasts about 0.75 s.");
      prm.declare_entry("Poisson's ratio",
                        "0.2",
                        Patterns::Double(-1., 0.5),
                        "nu, in (-1, 0.5).");
      prm.declare_entry("Density",
                        "1",
                        Patterns::Double(0.),
                        "rho, kg/m^3 (> 0).");
      prm.leave_subsection();
      prm.leave_subsection();
    }
  } // namespace

  double
  Parameters::symmetry_factor() const
  {
    for (unsigned int b = 0; b < n_bodies(); ++b)
      if (const auto &body = bodies[b];
          !(body.symmetry_cut &&
            body.geometry.shape == BodyGeometry::Shape::half_disk))
        return 1.;
    return 2.;
  }

  double
  Parameters::smallest_body_size() const
  {
    double size = std::numeric_limits<double>::max();
    for (unsigned int b = 0; b < n_bodies(); ++b)
      {
        const BodyGeometry &geometry = bodies[b].geometry;
        if (geometry.shape == BodyGeometry::Shape::rectangle)
          {
            const auto diagonal = geometry.upper_right - geometry.lower_left;
            size                = std::min(size,
                            0.5 * std::min(std::abs(diagonal[0]),
                                           std::abs(diagonal[1])));
          }
        else
          size = std::min(size, geometry.radius);
      }
    return size;
  }

  void
  Parameters::declare(ParameterHandler &prm)
  {
    for (unsigned int b = 0; b < 2; ++b)
      declare_body(prm, b);

    prm.enter_subsection("Model");
    prm.declare_entry("Plane",
                      "strain",
                      Patterns::Selection("strain|stress"),
                      "Plane strain or plane stress.");
    prm.leave_subsection();

    prm.enter_subsection("Discretization");
    prm.declare_entry("Method",
                      "fea",
                      Patterns::Selection(
                        discretization_method_names.selection()),
                      "fea: Lagrange (FE_Q) or serendipity elements with "
                      "MappingQ on exact manifolds; iga: NURBS (exact "
                      "circles), one patch per coarse FEA cell (4 for a half "
                      "disk), glued C0, so FEA and IGA share the coarse "
                      "mesh and the number of elements at every level.");
    prm.declare_entry("FEA element",
                      "lagrange",
                      Patterns::Selection(fea_element_names.selection()),
                      "Method = fea only. lagrange: FE_Q(Degree) (Q9 for "
                      "degree 2); serendipity: the 8-node quadratic element "
                      "of the source study (Degree = 2; row-sum lumping is "
                      "refused for it: negative corner masses).");
    prm.declare_entry("Degree",
                      "2",
                      Patterns::Integer(1, 6),
                      "Polynomial degree of the elements or splines.");
    prm.declare_entry("Global refinements",
                      "3",
                      Patterns::Integer(0, 10),
                      "Uniform refinements of the coarse mesh (IGA: knot "
                      "spans halved in each direction).");
    prm.declare_entry("Local refinements",
                      "0",
                      Patterns::Integer(0, 10),
                      "Further refinements near the refinement centre: FEA "
                      "refines the cells with a vertex within the refinement "
                      "radius; IGA halves the knot spans that carry such "
                      "elements, along whole knot lines (strips through "
                      "the patches).");
    prm.declare_entry("Refinement center",
                      "0, 0",
                      Patterns::List(Patterns::Double(), 2, 2),
                      "Where contact happens, m.");
    prm.declare_entry("Refinement radius",
                      "2",
                      Patterns::Double(0.),
                      "Radius of the locally refined zone, m.");
    prm.leave_subsection();

    prm.enter_subsection("Parallel");
    prm.declare_entry(
      "Load balancing",
      "automatic",
      Patterns::Selection(load_balancing_names.selection()),
      "On 2 MPI ranks with lumped mass: the rows near the ranks' interface "
      "(bodies split), or a body's rows farthest from its contact surface "
      "(bodies whole on ranks, up to 30 % of the body), "
      "move between them at run time towards equal times per step "
      "(measured), stay where the partition put them (off), or move one "
      "layer per step back and forth (sweep: a check of the machinery); "
      "claimed: both ranks hold those rows, and each step's pass shares "
      "them as the ranks reach them (both ranks on one node); shared "
      "memory: claimed, with the bodies' state in memory both ranks map, "
      "so that the step sends no message (both ranks on one node); "
      "automatic: shared memory for bodies whole on ranks where both "
      "ranks are on one node and /dev/shm has room for twice a body's "
      "state (40 bytes per unknown), else measured. The results have the "
      "same bits in every case.");
    prm.declare_entry(
      "Distribution",
      "automatic",
      Patterns::Selection("automatic|split"),
      "How the deformable bodies go to the MPI ranks. automatic: with as "
      "many ranks as bodies, bodies of equal size (unknowns within 5 %) and "
      "a lumped mass without hanging nodes, bipenalty or mass "
      "redistribution, each body whole on a rank of its own (the bodies "
      "share no cell: the partition with no cut; the ranks exchange the "
      "contact surfaces only); else every body split over all ranks. "
      "split: every body split over all ranks.");
    prm.declare_entry(
      "Thread partition",
      "dynamic",
      Patterns::Selection("dynamic|by body"),
      "How the threads of a process share the rows of the bodies' passes. "
      "dynamic: in blocks of 4096 rows that the threads take as they come; "
      "by body: each body's pass is one task, its rows on one thread (the "
      "bodies side by side): the static split of 2 MPI ranks with the "
      "bodies whole on ranks, without messages, to measure what the "
      "dynamic sharing gains on a machine. The results have the same bits "
      "either way.");
    prm.declare_entry(
      "Contact point exchange",
      "automatic",
      Patterns::Selection(point_exchange_names.selection()),
      "Where several MPI ranks share the contact's Gauss points (ranks that "
      "meet at every step, or whose bodies' state lies in shared memory), "
      "how each gets what the others' projections found. automatic: in "
      "memory all ranks map where they are on one node, else in one "
      "MPI_Allgather per evaluation; messages: MPI_Allgather always (to "
      "compare the two). The results have the same bits either way.");
    prm.leave_subsection();

    prm.enter_subsection("Mass matrix");
    prm.declare_entry("Scheme",
                      "HRZ",
                      Patterns::Selection(mass_scheme_names.selection()),
                      "consistent (solved with a factorisation computed "
                      "once), row-sum or HRZ lumping.");
    prm.leave_subsection();

    prm.enter_subsection("Contact");
    prm.declare_entry("Penalty",
                      "1e5",
                      PositiveNumberOrAuto(),
                      "eps_N, Pa/m: traction per unit penetration (> 0), or "
                      "auto: Penalty scale factor times mu / dt^2, mu the "
                      "contact surfaces' mean mass per length (reduced for "
                      "two bodies), dt the stable step bound without "
                      "contact. auto also sets Obstacle/Penalty.");
    prm.declare_entry("Penalty scale factor",
                      "0.5",
                      Patterns::Double(0.),
                      "s of Penalty = auto (> 0): the contact mode then has "
                      "omega_c dt_bulk = sqrt(s). The benchmark's 1e5 Pa/m "
                      "is s = 2.8 (FEA Q9 HRZ) and 7.4 (IGA p2 HRZ) on its "
                      "level-4 mesh (doc/formulation.md).");
    prm.declare_entry("Penalty per pass",
                      "half",
                      Patterns::Selection(penalty_per_pass_names.selection()),
                      "Two-pass convention: half puts eps_N/2 on each pass, "
                      "so that both together act like one penalty eps_N; "
                      "full puts eps_N on each (effective 2 eps_N).");
    prm.declare_entry("Quadrature points per face",
                      "4",
                      Patterns::Integer(1, 20),
                      "Gauss points of the contact integral on each face.");
    prm.declare_entry(
      "Damping ratio",
      "0",
      Patterns::Double(0., 1.),
      "Viscous contact damping as a fraction of the critical damping "
      "2 sqrt(eps mu) of the penalty spring on the surface mass mu, in "
      "[0, 1]; 0 = none. It damps the contact chatter; the stable step "
      "bound is reduced by sqrt(1 + xi^2) - xi. Applies to every contact, "
      "rigid obstacles included (doc/formulation.md).");
    prm.declare_entry(
      "Bipenalty",
      "false",
      Patterns::Bool(),
      "Bipenalty method (two-body contact, lumped mass): next to the "
      "stiffness penalty, a mass penalty eps_m lumped onto the unknowns of "
      "every active Gauss point and of its projection, per component, each "
      "step. eps_m = Bipenalty mass scale factor x the critical mass "
      "penalty of the stable step with the stiffness penalty (the smallest "
      "that does not lower it). Not with Damping ratio > 0, a consistent "
      "mass or an Obstacle (doc/formulation.md).");
    prm.declare_entry("Bipenalty mass scale factor",
                      "1",
                      Patterns::Double(0.),
                      "f > 0: eps_m = f x the critical mass penalty; the "
                      "stable step is min(1, sqrt(f)) times that with the "
                      "stiffness penalty alone.");
    prm.declare_entry("Bipenalty switching",
                      "momentum",
                      Patterns::Selection("momentum|velocity"),
                      "Where the mass penalty of an unknown changes (the "
                      "active set changes): momentum keeps (m + m_p) v "
                      "(central differences in momentum form); velocity "
                      "keeps v (the mass comes with the node's velocity and "
                      "pumps momentum into the contact when it chatters; "
                      "doc/formulation.md).");
    prm.declare_entry(
      "Mass redistribution",
      "false",
      Patterns::Bool(),
      "Chatter remedy: the unknowns of the contact surfaces carry no mass "
      "(their lumped mass goes to the interior unknowns next to them, total "
      "mass and centre of mass kept) and are solved from quasi-static "
      "equilibrium every step (Newton with the contact tangent). Lumped "
      "mass (row-sum, HRZ) only, not with Damping ratio > 0 nor with Local "
      "refinements > 0; the stable step is that of the interior "
      "(doc/formulation.md).");
    prm.leave_subsection();

    prm.enter_subsection("Obstacle");
    prm.declare_entry("Type",
                      "none",
                      Patterns::Selection("none|plane|cylinder|channel"),
                      "A rigid, fixed, frictionless obstacle. none: the "
                      "scene is Body 1 against Body 2 (two-pass contact). "
                      "plane or cylinder: the scene is Body 1 against the "
                      "obstacle (penalty contact of Body 1's arc, see "
                      "Penalty below); Body 2 is then ignored entirely. "
                      "channel: two parallel planes, the plane and its "
                      "mirror through Opposite point, Body 1 between them "
                      "(repeated impacts; needs Analytic reference = none).");
    prm.declare_entry("Point",
                      "0, 0",
                      Patterns::List(Patterns::Double(), 2, 2),
                      "plane: a point of the plane, m.");
    prm.declare_entry("Normal",
                      "0, 1",
                      Patterns::List(Patterns::Double(), 2, 2),
                      "plane: normal pointing out of the obstacle, towards "
                      "the body (non-zero; normalised by the program).");
    prm.declare_entry("Opposite point",
                      "0, 10",
                      Patterns::List(Patterns::Double(), 2, 2),
                      "channel: a point of the second plane, whose normal "
                      "is -Normal, m (on the side Normal points to).");
    prm.declare_entry("Center",
                      "0, -4",
                      Patterns::List(Patterns::Double(), 2, 2),
                      "cylinder: centre, m; the body is outside the circle.");
    prm.declare_entry("Radius",
                      "4",
                      Patterns::Double(),
                      "cylinder: radius, m (> 0).");
    prm.declare_entry("Penalty",
                      "2e5",
                      Patterns::Double(),
                      "eps_obstacle, Pa/m (> 0): traction per unit "
                      "penetration of the obstacle. A symmetric two-body "
                      "impact with Contact/Penalty = eps_N and Penalty per "
                      "pass = half is reproduced against its symmetry plane "
                      "with 2 eps_N (each body penetrates half the total "
                      "gap; see doc/formulation.md).");
    prm.leave_subsection();

    prm.enter_subsection("Time integration");
    prm.declare_entry(
      "Time step",
      "auto",
      PositiveNumberOrAuto(),
      "Central difference step, s (> 0), or auto: the safety factor times "
      "the guaranteed stable step bound, which includes the contact "
      "penalty (doc/stability.md).");
    prm.declare_entry("Time step safety factor",
                      "0.9",
                      Patterns::Double(0., 1.),
                      "Fraction of the stable step bound taken with "
                      "Time step = auto, in (0, 1].");
    prm.declare_entry("Contact activation margin",
                      "2",
                      Patterns::Double(1.),
                      "The stable step bound counts the contact penalty "
                      "springs this many times (>= 1): penalty contact that "
                      "opens and closes inside a step pumps energy at steps "
                      "the linearised bound (margin 1) calls stable "
                      "(doc/stability.md).");
    prm.declare_entry("Allow time step above the stable estimate",
                      "false",
                      Patterns::Bool(),
                      "A given time step above the stable step bound is "
                      "refused unless this is true (the stability monitor "
                      "still stops a run that blows up).");
    prm.declare_entry("End time", "0.9", Patterns::Double(0.), "s (> 0).");
    prm.declare_entry("Energy growth tolerance",
                      "0.1",
                      Patterns::Double(0.),
                      "The run stops as unstable when the total energy "
                      "exceeds the input energy by this fraction of it.");
    prm.declare_entry("Maximum penetration",
                      "0.25",
                      Patterns::Double(0.),
                      "The run stops as unstable when a contact "
                      "penetration exceeds this fraction of the smallest "
                      "body size (radius, or half the shorter side).");
    prm.leave_subsection();

    prm.enter_subsection("Output");
    prm.declare_entry("Directory",
                      "output/hertz",
                      Patterns::Anything(),
                      "Created when the run starts; relative paths are "
                      "relative to the working directory.");
    prm.declare_entry("History interval",
                      "1",
                      Patterns::Integer(1),
                      "Steps between rows of history.csv.");
    prm.declare_entry("VTU interval",
                      "100",
                      Patterns::Integer(0),
                      "Steps between ParaView outputs (0: none).");
    prm.declare_entry("VTU cells",
                      "higher order",
                      Patterns::Selection("higher order|subdivided"),
                      "higher order: one VTK cell per element with the exact "
                      "geometry and fields (Lagrange cells for FEA, rational "
                      "Bezier cells for IGA; ParaView 5.9 or later); "
                      "subdivided: VTU subdivisions linear quadrilaterals "
                      "per element.");
    prm.declare_entry("VTU compression",
                      "false",
                      Patterns::Bool(),
                      "With VTU cells = higher order: compress the arrays "
                      "with zlib (fastest level). Off, the arrays are "
                      "written raw (appended binary), about 1.5 times "
                      "larger and several times faster.");
    prm.declare_entry("VTU subdivisions",
                      "2",
                      Patterns::Integer(1, 8),
                      "Subdivisions of each cell in the ParaView output "
                      "with VTU cells = subdivided.");
    prm.declare_entry("Pressure profile times",
                      "0.375",
                      Patterns::List(Patterns::Double(0.)),
                      "Times (s) at which the contact pressure along the "
                      "surface is written.");
    prm.declare_entry("Analytic reference",
                      "Gerl-Zippelius",
                      Patterns::Selection(approach_law_names.selection() +
                                          "|none"),
                      "Approach law of the quasi-static Hertz impact used "
                      "for the analytic columns (two disks only).");
    prm.declare_entry("Filter window",
                      "0.01",
                      Patterns::Double(0.),
                      "Width (s) of the centred moving average applied to "
                      "the contact force and pressure histories for the "
                      "filtered peaks of summary.json (raw peaks are given "
                      "too); history.csv holds the raw signals.");
    prm.declare_entry("Progress interval",
                      "10",
                      Patterns::Double(0., 100.),
                      "Percent of the run between progress lines.");
    prm.declare_entry(
      "Step times",
      "false",
      Patterns::Bool(),
      "Write step_times.csv: the end of each step on the "
      "machine's monotonic clock (s), for benchmarks that "
      "pause and resume runs (benchmarks/alternating_runs.py).");
    prm.leave_subsection();
  }

  void
  Parameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Model");
    const bool plane_strain = prm.get("Plane") == "strain";
    prm.leave_subsection();

    prm.enter_subsection("Discretization");
    method      = discretization_method_names.from_string(prm.get("Method"));
    fea_element = fea_element_names.from_string(prm.get("FEA element"));
    degree      = prm.get_integer("Degree");
    const unsigned int global  = prm.get_integer("Global refinements");
    const unsigned int local   = prm.get_integer("Local refinements");
    const auto   center_values = parse_doubles(prm.get("Refinement center"));
    const double refine_radius = prm.get_double("Refinement radius");
    prm.leave_subsection();

    for (unsigned int b = 0; b < 2; ++b)
      {
        auto &body = bodies[b];
        prm.enter_subsection(body_names[b]);
        const std::string shape = prm.get("Shape");
        body.geometry.shape =
          shape == "half disk" ?
            BodyGeometry::Shape::half_disk :
            (shape == "full disk" ? BodyGeometry::Shape::full_disk :
                                    BodyGeometry::Shape::rectangle);
        const auto c             = parse_doubles(prm.get("Center"));
        body.geometry.center     = Point<2>(c[0], c[1]);
        body.geometry.radius     = prm.get_double("Radius");
        const auto ll            = parse_doubles(prm.get("Lower left corner"));
        const auto ur            = parse_doubles(prm.get("Upper right corner"));
        body.geometry.lower_left = Point<2>(ll[0], ll[1]);
        body.geometry.upper_right = Point<2>(ur[0], ur[1]);
        const auto v              = parse_doubles(prm.get("Initial velocity"));
        body.initial_velocity[0]  = v[0];
        body.initial_velocity[1]  = v[1];
        body.symmetry_cut         = prm.get_bool("Symmetry cut");
        prm.enter_subsection("Material");
        body.material.youngs_modulus = prm.get_double("Young's modulus");
        body.material.poisson_ratio  = prm.get_double("Poisson's ratio");
        body.material.density        = prm.get_double("Density");
        body.material.plane_strain   = plane_strain;
        prm.leave_subsection();
        prm.leave_subsection();

        body.geometry.global_refinements = global;
        body.geometry.local_refinements  = local;
        body.geometry.refinement_center =
          Point<2>(center_values[0], center_values[1]);
        body.geometry.refinement_radius = refine_radius;
      }

    prm.enter_subsection("Mass matrix");
    mass_scheme = mass_scheme_names.from_string(prm.get("Scheme"));
    prm.leave_subsection();

    prm.enter_subsection("Parallel");
    {
      load_balancing =
        load_balancing_names.from_string(prm.get("Load balancing"));
      split_every_body           = prm.get("Distribution") == "split";
      pass_of_body_on_one_thread = prm.get("Thread partition") == "by body";
      contact_point_exchange =
        point_exchange_names.from_string(prm.get("Contact point exchange"));
    }
    prm.leave_subsection();

    prm.enter_subsection("Contact");
    automatic_penalty    = prm.get("Penalty") == "auto";
    contact.penalty      = automatic_penalty ? 0. : prm.get_double("Penalty");
    penalty_scale_factor = prm.get_double("Penalty scale factor");
    contact.penalty_per_pass =
      penalty_per_pass_names.from_string(prm.get("Penalty per pass"));
    contact.n_quadrature_points = prm.get_integer("Quadrature points per face");
    contact.damping_ratio       = prm.get_double("Damping ratio");
    bipenalty                   = prm.get_bool("Bipenalty");
    bipenalty_mass_scale_factor = prm.get_double("Bipenalty mass scale factor");
    bipenalty_momentum_switching = prm.get("Bipenalty switching") == "momentum";
    mass_redistribution          = prm.get_bool("Mass redistribution");
    prm.leave_subsection();

    prm.enter_subsection("Obstacle");
    obstacle.type           = prm.get("Type");
    const auto p            = parse_doubles(prm.get("Point"));
    obstacle.point          = Point<2>(p[0], p[1]);
    const auto n            = parse_doubles(prm.get("Normal"));
    obstacle.normal[0]      = n[0];
    obstacle.normal[1]      = n[1];
    const auto op           = parse_doubles(prm.get("Opposite point"));
    obstacle.opposite_point = Point<2>(op[0], op[1]);
    const auto oc           = parse_doubles(prm.get("Center"));
    obstacle.center         = Point<2>(oc[0], oc[1]);
    obstacle.radius         = prm.get_double("Radius");
    obstacle.penalty        = prm.get_double("Penalty");
    prm.leave_subsection();

    prm.enter_subsection("Time integration");
    const std::string step_text = prm.get("Time step");
    automatic_time_step         = (step_text == "auto");
    time_step                 = automatic_time_step ? 0. : std::stod(step_text);
    time_step_safety_factor   = prm.get_double("Time step safety factor");
    contact_activation_margin = prm.get_double("Contact activation margin");
    allow_time_step_above_bound =
      prm.get_bool("Allow time step above the stable estimate");
    end_time                = prm.get_double("End time");
    energy_growth_tolerance = prm.get_double("Energy growth tolerance");
    maximum_penetration     = prm.get_double("Maximum penetration");
    prm.leave_subsection();

    prm.enter_subsection("Output");
    output_directory  = prm.get("Directory");
    history_interval  = prm.get_integer("History interval");
    vtu_interval      = prm.get_integer("VTU interval");
    vtu_subdivisions  = prm.get_integer("VTU subdivisions");
    vtu_higher_order  = prm.get("VTU cells") == "higher order";
    vtu_compression   = prm.get_bool("VTU compression");
    profile_times     = parse_doubles(prm.get("Pressure profile times"));
    approach_law      = prm.get("Analytic reference");
    progress_interval = prm.get_double("Progress interval");
    filter_window     = prm.get_double("Filter window");
    step_times        = prm.get_bool("Step times");
    prm.leave_subsection();
  }

  Parameters
  read_parameters(const std::string &filename)
  {
    if (!std::filesystem::is_regular_file(filename))
      throw InputError("parameter file '" + filename +
                       "' does not exist or is not a file");

    check_file_structure(filename);

    ParameterHandler prm;
    Parameters::declare(prm);
    try
      {
        prm.parse_input(filename, "", false, true);
      }
    catch (const ExceptionBase &e)
      {
        std::ostringstream message;
        e.print_info(message);
        throw InputError("in parameter file '" + filename +
                         "': " + message.str());
      }

    Parameters parameters;
    parameters.parse(prm);

    // Values the patterns cannot express.
    const auto require = [&](const bool         condition,
                             const std::string &parameter,
                             const auto        &value,
                             const std::string &allowed) {
      if (!condition)
        {
          std::ostringstream message;
          message << "in parameter file '" << filename << "': parameter '"
                  << parameter << "' has the value " << value << "; "
                  << allowed;
          throw InputError(message.str());
        }
    };
    if (parameters.bipenalty)
      {
        require(parameters.mass_scheme != MassScheme::consistent,
                "Contact/Bipenalty",
                "true",
                "the bipenalty adds its mass to a lumped diagonal: it needs "
                "Mass matrix/Scheme = row-sum or HRZ (here consistent)");
        require(parameters.contact.damping_ratio == 0.,
                "Contact/Bipenalty",
                "true",
                "it cannot be combined with Contact/Damping ratio = " +
                  std::to_string(parameters.contact.damping_ratio) +
                  " (the damping's ratio refers to the surface mass without "
                  "the mass penalty): set one of them off");
        require(!parameters.obstacle.active(),
                "Contact/Bipenalty",
                "true",
                "it is implemented for the two-body contact only, not with "
                "Obstacle/Type = " +
                  parameters.obstacle.type);
        require(parameters.bipenalty_mass_scale_factor > 0.,
                "Contact/Bipenalty mass scale factor",
                parameters.bipenalty_mass_scale_factor,
                "it must be positive");
      }
    require(parameters.fea_element == FEAElement::lagrange ||
              (parameters.method == DiscretizationMethod::fea &&
               parameters.degree == 2),
            "Discretization/FEA element",
            to_string(parameters.fea_element),
            "serendipity needs Method = fea and Degree = 2 (here " +
              to_string(parameters.method) + ", " +
              std::to_string(parameters.degree) + ")");
    require(parameters.fea_element == FEAElement::lagrange ||
              parameters.mass_scheme != MassScheme::row_sum,
            "Mass matrix/Scheme",
            "row-sum",
            "row-sum lumping of the serendipity element gives negative "
            "corner masses (-1/12 of the element mass); use HRZ or "
            "consistent");
    if (parameters.mass_redistribution)
      {
        require(parameters.mass_scheme != MassScheme::consistent,
                "Mass matrix/Scheme",
                "consistent",
                "'Contact/Mass redistribution = true' needs a lumped mass "
                "(row-sum or HRZ): it moves lumped nodal masses; set "
                "Mass redistribution = false or a lumped scheme");
        require(parameters.contact.damping_ratio == 0.,
                "Contact/Damping ratio",
                parameters.contact.damping_ratio,
                "it must be 0 with 'Contact/Mass redistribution = true' "
                "(two remedies of the same chatter; the massless surface "
                "has no velocity of its own to damp)");
        for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
          require(parameters.bodies[b].geometry.local_refinements == 0,
                  "Discretization/Local refinements",
                  parameters.bodies[b].geometry.local_refinements,
                  "it must be 0 with 'Contact/Mass redistribution = true' "
                  "(hanging nodes on the contact surface are not "
                  "supported)");
        require(!parameters.bipenalty,
                "Contact/Bipenalty",
                "true",
                "it cannot be combined with 'Contact/Mass redistribution = "
                "true' (the mass penalty would sit on massless unknowns): "
                "set one of them off");
      }
    // With an obstacle Body 2 is ignored: not checked either.
    for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
      {
        const auto       &body = parameters.bodies[b];
        const std::string s    = std::string(body_names[b]) + "/";
        require(body.geometry.radius > 0.,
                s + "Radius",
                body.geometry.radius,
                "it must be positive");
        require(body.material.youngs_modulus > 0.,
                s + "Material/Young's modulus",
                body.material.youngs_modulus,
                "it must be positive");
        require(body.material.density > 0.,
                s + "Material/Density",
                body.material.density,
                "it must be positive");
        require(body.material.poisson_ratio < 0.5 &&
                  body.material.poisson_ratio > -1.,
                s + "Material/Poisson's ratio",
                body.material.poisson_ratio,
                "it must lie in (-1, 0.5)");
        if (body.geometry.shape == BodyGeometry::Shape::rectangle)
          for (unsigned int d = 0; d < 2; ++d)
            require(body.geometry.upper_right[d] > body.geometry.lower_left[d],
                    s + "Upper right corner",
                    body.geometry.upper_right[d],
                    "each coordinate must exceed the lower left corner's");
      }
    if (!parameters.obstacle.active() &&
        !parameters.automatic_penalty) // else not used
      require(parameters.contact.penalty > 0.,
              "Contact/Penalty",
              parameters.contact.penalty,
              "it must be positive");
    require(parameters.automatic_time_step || parameters.time_step > 0.,
            "Time integration/Time step",
            parameters.time_step,
            "it must be positive or auto");
    require(parameters.time_step_safety_factor > 0.,
            "Time integration/Time step safety factor",
            parameters.time_step_safety_factor,
            "it must lie in (0, 1]");
    require(parameters.end_time > 0.,
            "Time integration/End time",
            parameters.end_time,
            "it must be positive");
    require(parameters.automatic_time_step ||
              parameters.time_step <= parameters.end_time,
            "Time integration/Time step",
            parameters.time_step,
            "it must not exceed the end time");
    const auto &obstacle = parameters.obstacle;
    if (obstacle.type == "channel")
      {
        require((obstacle.opposite_point - obstacle.point) * obstacle.normal >
                  0.,
                "Obstacle/Opposite point",
                "(" + point_string(obstacle.opposite_point) + ")",
                "the second plane of a channel must lie on the side that "
                "Obstacle/Normal points to");
        require(parameters.approach_law == "none",
                "Output/Analytic reference",
                parameters.approach_law,
                "a channel has no analytic Hertz reference: set none");
      }
    if (obstacle.type == "plane" || obstacle.type == "channel")
      require(obstacle.normal.norm() > 0. &&
                std::isfinite(obstacle.normal.norm()),
              "Obstacle/Normal",
              "(" + point_string(Point<2>(obstacle.normal)) + ")",
              "the normal of the plane must be a non-zero vector");
    if (obstacle.type == "cylinder")
      require(obstacle.radius > 0.,
              "Obstacle/Radius",
              obstacle.radius,
              "it must be positive");
    if (obstacle.active() && !parameters.automatic_penalty)
      require(obstacle.penalty > 0.,
              "Obstacle/Penalty",
              obstacle.penalty,
              "it must be positive");
    if (obstacle.type == "plane" && parameters.approach_law != "none")
      require(parameters.bodies[0].initial_velocity *
                  (obstacle.normal / obstacle.normal.norm()) <
                0.,
              "Body 1/Initial velocity",
              "(" +
                point_string(Point<2>(parameters.bodies[0].initial_velocity)) +
                ")",
              "the analytic Hertz reference against a rigid plane needs "
              "Body 1 to move towards the plane (velocity . Obstacle/Normal "
              "< 0): change it or set Output/Analytic reference = none");
    if (parameters.approach_law != "none")
      for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
        require(parameters.bodies[b].geometry.shape !=
                  BodyGeometry::Shape::rectangle,
                std::string(body_names[b]) + "/Shape",
                "rectangle",
                "the analytic Hertz reference needs disks: set "
                "Output/Analytic reference = none");
    // Values of valid form but beyond what double precision carries
    // through the assembly (squares of lengths and moduli, energies) or
    // beyond any physical meaning: refused by name rather than failing
    // inside deal.II. Coordinates may lie at most 1e6 body sizes from the
    // origin, so that round-off in them stays below 1e-10 of a body.
    const auto within = [&](const double       value,
                            const double       low,
                            const double       high,
                            const std::string &parameter,
                            const std::string &unit) {
      std::ostringstream allowed;
      allowed << "it must lie in [" << low << ", " << high << "] " << unit;
      require(std::isfinite(value) && value >= low && value <= high,
              parameter,
              value,
              allowed.str());
    };
    const double size        = parameters.smallest_body_size();
    const double coordinate  = 1e6 * size;
    const auto   near_origin = [&](const Point<2>    &point,
                                 const std::string &parameter) {
      std::ostringstream allowed;
      allowed << "a point must lie within " << coordinate
              << " m of the origin (1e6 times the smallest body size, " << size
              << " m) to keep its precision: move the scene";
      require(std::isfinite(point.norm()) && point.norm() <= coordinate,
              parameter,
              "(" + point_string(point) + ")",
              allowed.str());
    };
    // Coordinates are checked last, once the sizes are known to be sound.
    std::vector<std::pair<Point<2>, std::string>> points;
    for (unsigned int b = 0; b < parameters.n_bodies(); ++b)
      {
        const auto       &body = parameters.bodies[b];
        const std::string s    = std::string(body_names[b]) + "/";
        if (body.geometry.shape == BodyGeometry::Shape::rectangle)
          {
            const auto diagonal =
              body.geometry.upper_right - body.geometry.lower_left;
            within(std::min(diagonal[0], diagonal[1]),
                   1e-9,
                   1e9,
                   s + "Upper right corner (the shorter side)",
                   "m");
            within(std::max(diagonal[0], diagonal[1]),
                   1e-9,
                   1e9,
                   s + "Upper right corner (the longer side)",
                   "m");
            points.emplace_back(body.geometry.lower_left,
                                s + "Lower left corner");
            points.emplace_back(body.geometry.upper_right,
                                s + "Upper right corner");
          }
        else
          {
            within(body.geometry.radius, 1e-9, 1e9, s + "Radius", "m");
            points.emplace_back(body.geometry.center, s + "Center");
          }
        within(body.material.youngs_modulus,
               1e-6,
               1e15,
               s + "Material/Young's modulus",
               "Pa");
        within(body.material.density,
               1e-6,
               1e9,
               s + "Material/Density",
               "kg/m^3");
        require(body.initial_velocity.norm() <= 1e8,
                s + "Initial velocity",
                "(" + point_string(Point<2>(body.initial_velocity)) + ")",
                "its magnitude must not exceed 1e8 m/s");
      }
    if (parameters.bodies[0].geometry.local_refinements > 0)
      {
        points.emplace_back(parameters.bodies[0].geometry.refinement_center,
                            "Discretization/Refinement center");
        within(parameters.bodies[0].geometry.refinement_radius,
               1e-9,
               1e9,
               "Discretization/Refinement radius",
               "m");
      }
    if (parameters.automatic_penalty)
      within(parameters.penalty_scale_factor,
             1e-6,
             1e6,
             "Contact/Penalty scale factor",
             "");
    else if (!parameters.obstacle.active())
      within(parameters.contact.penalty, 1e-6, 1e20, "Contact/Penalty", "Pa/m");
    if (parameters.obstacle.active())
      {
        const auto &obstacle = parameters.obstacle;
        if (!parameters.automatic_penalty)
          within(obstacle.penalty, 1e-6, 1e20, "Obstacle/Penalty", "Pa/m");
        if (obstacle.type == "cylinder")
          {
            within(obstacle.radius, 1e-9, 1e9, "Obstacle/Radius", "m");
            points.emplace_back(obstacle.center, "Obstacle/Center");
          }
        else
          points.emplace_back(obstacle.point, "Obstacle/Point");
        if (obstacle.type == "channel")
          points.emplace_back(obstacle.opposite_point,
                              "Obstacle/Opposite point");
      }
    // A moving average far longer than the run means nothing (and its width
    // in steps must stay countable).
    require(parameters.filter_window <= 10. * parameters.end_time,
            "Output/Filter window",
            parameters.filter_window,
            "it must not exceed 10 times the end time (" +
              std::to_string(10. * parameters.end_time) + " s)");
    for (const auto &[point, parameter] : points)
      near_origin(point, parameter);
    return parameters;
  }

  void
  print_default_parameters(std::ostream &out)
  {
    ParameterHandler prm;
    Parameters::declare(prm);
    out << "# isoimpact parameter file with every parameter, its default and "
           "its documentation.\n";
    prm.print_parameters(out, ParameterHandler::PRM);
  }
} // namespace isoimpact
