// Ready-made NURBS patches and the patch text format.
#include <isoimpact/nurbs/geometries.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

using namespace dealii;

namespace isoimpact
{
  namespace nurbs
  {
    namespace
    {
      // Control net of a 3 x 3 quadratic Bezier patch from local points
      // (scaled by radius, shifted by center), index i + 3 j.
      PatchGeometry<2>
      quadratic_bezier_patch(const std::array<dealii::Point<2>, 9> &local,
                             const std::array<double, 9>           &weights,
                             const double                           scale,
                             const dealii::Point<2>                &center)
      {
        const KnotVector              kv({0., 0., 0., 1., 1., 1.}, 2);
        std::vector<dealii::Point<2>> points(9);
        for (unsigned int a = 0; a < 9; ++a)
          points[a] = center + scale * local[a];
        PatchGeometry<2> geometry;
        geometry.patch =
          NURBSPatch<2>({{kv, kv}},
                        points,
                        std::vector<double>(weights.begin(), weights.end()));
        return geometry;
      }

      void
      check_radius(const std::string &what, const double radius)
      {
        AssertThrow(std::isfinite(radius) && radius > 0.,
                    dealii::ExcMessage(what + ": radius " + to_string(radius) +
                                       " is not allowed; it must be positive "
                                       "and finite"));
      }

      // The message of a deal.II exception on one line.
      std::string
      exception_text(const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        // deal.II indents and wraps the message: undo that.
        std::istringstream words(info.str());
        std::string        text, word;
        while (words >> word)
          text += (text.empty() ? "" : " ") + word;
        return text;
      }

      // One line of a patch file without its comment, split into words.
      struct Line
      {
        unsigned int             number;
        std::vector<std::string> words;
      };
    } // namespace



    template <int dim, int spacedim>
    std::vector<unsigned int>
    PatchGeometry<dim, spacedim>::sides_of_kind(const SideKind kind) const
    {
      std::vector<unsigned int> result;
      for (unsigned int f = 0; f < 2 * dim; ++f)
        if (side_kinds[f] == kind)
          result.push_back(f);
      return result;
    }



    PatchGeometry<2>
    half_disk(const double radius, const dealii::Point<2> &center)
    {
      check_radius("half disk", radius);
      const double s = 1. / std::sqrt(2.);
      // Rows xi_1 = 0 (lower arc C-E), middle, xi_1 = 1 (upper cut O-T).
      const std::array<dealii::Point<2>, 9> local   = {{{0., -1.},
                                                        {1., -1.},
                                                        {1., 0.},
                                                        {0., -0.5},
                                                        {0.8, 0.},
                                                        {1., 1.},
                                                        {0., 0.},
                                                        {0., 0.5},
                                                        {0., 1.}}};
      const std::array<double, 9>           weights = {
                  {1., s, 1., 1., 1., s, 1., 1., 1.}};
      PatchGeometry<2> geometry =
        quadratic_bezier_patch(local, weights, radius, center);
      geometry.side_kinds[half_disk_sides::lower_symmetry] = SideKind::symmetry;
      geometry.side_kinds[half_disk_sides::upper_arc]      = SideKind::arc;
      geometry.side_kinds[half_disk_sides::lower_arc]      = SideKind::arc;
      geometry.side_kinds[half_disk_sides::upper_symmetry] = SideKind::symmetry;
      geometry.has_contact_point                           = true;
      geometry.contact_parameter = dealii::Point<2>(0., 0.);
      geometry.contact_point     = center + dealii::Point<2>(0., -radius);
      return geometry;
    }



    PatchGeometry<2>
    full_disk(const double radius, const dealii::Point<2> &center)
    {
      check_radius("full disk", radius);
      const double s = 1. / std::sqrt(2.), r2 = std::sqrt(2.);
      const std::array<dealii::Point<2>, 9> local = {{{-s, -s},
                                                      {0., -r2},
                                                      {s, -s},
                                                      {-r2, 0.},
                                                      {0., 0.},
                                                      {r2, 0.},
                                                      {-s, s},
                                                      {0., r2},
                                                      {s, s}}};
      const std::array<double, 9> weights = {{1., s, 1., s, 1., s, 1., s, 1.}};
      PatchGeometry<2>            geometry =
        quadratic_bezier_patch(local, weights, radius, center);
      geometry.side_kinds.fill(SideKind::arc);
      return geometry;
    }



    PatchGeometry<2>
    quadrilateral(const std::array<dealii::Point<2>, 4> &vertices,
                  const std::array<SideKind, 4>         &side_kinds,
                  const dealii::Point<2>                &arc_center)
    {
      // Homogeneous control net (w x, w y, w), index i + 3 j.
      std::array<dealii::Point<3>, 9> net;
      const auto homogeneous = [](const dealii::Point<2> &x, const double w) {
        return dealii::Point<3>(w * x[0], w * x[1], w);
      };
      const std::array<unsigned int, 4> corner_index = {{0, 2, 6, 8}};
      for (unsigned int v = 0; v < 4; ++v)
        net[corner_index[v]] = homogeneous(vertices[v], 1.);
      // Side f: its end vertices and the index of its middle control point.
      const std::array<std::array<unsigned int, 2>, 4> ends = {
        {{{0, 2}}, {{1, 3}}, {{0, 1}}, {{2, 3}}}};
      const std::array<unsigned int, 4> middle_index = {{3, 5, 1, 7}};
      for (unsigned int f = 0; f < 4; ++f)
        {
          const dealii::Point<2> &a = vertices[ends[f][0]];
          const dealii::Point<2> &b = vertices[ends[f][1]];
          if (side_kinds[f] != SideKind::arc)
            {
              net[middle_index[f]] = homogeneous(0.5 * (a + b), 1.);
              continue;
            }
          const double radius = a.distance(arc_center);
          check_radius("quadrilateral arc side", radius);
          AssertThrow(
            std::abs(b.distance(arc_center) - radius) <= 1e-10 * radius,
            dealii::ExcMessage("quadrilateral: the ends of arc side " +
                               std::to_string(f) + " are at distances " +
                               to_string(radius) + " and " +
                               to_string(b.distance(arc_center)) +
                               " from the arc centre; they must be equal"));
          const dealii::Tensor<1, 2> mid = 0.5 * (a + b) - arc_center;
          // cos of half the opening angle.
          const double half_cosine = mid.norm() / radius;
          AssertThrow(half_cosine > 1e-6,
                      dealii::ExcMessage(
                        "quadrilateral: arc side " + std::to_string(f) +
                        " spans half a circle or more; split the patch"));
          const dealii::Point<2> apex =
            arc_center + (radius / half_cosine) * (mid / mid.norm());
          net[middle_index[f]] = homogeneous(apex, half_cosine);
        }
      net[4] = dealii::Point<3>();
      for (const unsigned int m : middle_index)
        net[4] += 0.5 * net[m];
      for (const unsigned int c : corner_index)
        net[4] -= 0.25 * net[c];
      AssertThrow(net[4][2] > 0.,
                  dealii::ExcMessage("quadrilateral: the blended interior "
                                     "weight is not positive"));

      const KnotVector              kv({0., 0., 0., 1., 1., 1.}, 2);
      std::vector<dealii::Point<2>> points(9);
      std::vector<double>           weights(9);
      for (unsigned int a = 0; a < 9; ++a)
        {
          weights[a] = net[a][2];
          points[a] =
            dealii::Point<2>(net[a][0] / weights[a], net[a][1] / weights[a]);
        }
      PatchGeometry<2> geometry;
      geometry.patch = NURBSPatch<2>({{kv, kv}}, points, weights);
      std::copy(side_kinds.begin(),
                side_kinds.end(),
                geometry.side_kinds.begin());
      return geometry;
    }



    PatchGeometry<2>
    quarter_annulus(const double            inner_radius,
                    const double            outer_radius,
                    const dealii::Point<2> &center)
    {
      check_radius("quarter annulus (inner)", inner_radius);
      check_radius("quarter annulus (outer)", outer_radius);
      AssertThrow(inner_radius < outer_radius,
                  dealii::ExcMessage("quarter annulus: inner radius " +
                                     to_string(inner_radius) +
                                     " is not smaller than outer radius " +
                                     to_string(outer_radius) +
                                     "; the inner radius must be smaller"));
      const double s     = 1. / std::sqrt(2.);
      const double ratio = inner_radius / outer_radius;
      const double r[3]  = {ratio, 0.5 * (ratio + 1.), 1.};
      // Direction 0 radial, direction 1 along the angle.
      std::array<dealii::Point<2>, 9> local;
      std::array<double, 9>           weights;
      for (unsigned int i = 0; i < 3; ++i)
        {
          local[i]       = dealii::Point<2>(r[i], 0.);
          local[i + 3]   = dealii::Point<2>(r[i], r[i]);
          local[i + 6]   = dealii::Point<2>(0., r[i]);
          weights[i]     = 1.;
          weights[i + 3] = s;
          weights[i + 6] = 1.;
        }
      PatchGeometry<2> geometry =
        quadratic_bezier_patch(local, weights, outer_radius, center);
      geometry.side_kinds = {
        {SideKind::arc, SideKind::arc, SideKind::symmetry, SideKind::symmetry}};
      return geometry;
    }



    PatchGeometry<2>
    rectangle(const dealii::Point<2> &corner1,
              const dealii::Point<2> &corner2,
              const unsigned int      degree)
    {
      dealii::Point<2> lower, upper;
      for (unsigned int d = 0; d < 2; ++d)
        {
          AssertThrow(std::isfinite(corner1[d]) && std::isfinite(corner2[d]) &&
                        corner1[d] != corner2[d],
                      dealii::ExcMessage("rectangle: corners have coordinate " +
                                         std::to_string(d) + " equal to " +
                                         to_string(corner1[d]) + " and " +
                                         to_string(corner2[d]) +
                                         "; they must be finite and differ"));
          lower[d] = std::min(corner1[d], corner2[d]);
          upper[d] = std::max(corner1[d], corner2[d]);
        }
      std::vector<double> knots(degree + 1, 0.);
      knots.insert(knots.end(), degree + 1, 1.);
      const KnotVector              kv(knots, degree);
      std::vector<dealii::Point<2>> points;
      for (unsigned int j = 0; j <= degree; ++j)
        for (unsigned int i = 0; i <= degree; ++i)
          points.emplace_back(lower[0] + (upper[0] - lower[0]) * i / degree,
                              lower[1] + (upper[1] - lower[1]) * j / degree);
      PatchGeometry<2> geometry;
      geometry.patch = NURBSPatch<2>({{kv, kv}}, points);
      geometry.side_kinds.fill(SideKind::straight);
      return geometry;
    }



    template <int dim, int spacedim>
    PatchGeometry<dim, spacedim>
    read_patch(const std::string &filename)
    {
      std::ifstream in(filename);
      AssertThrow(in.good(),
                  dealii::ExcMessage("patch file '" + filename +
                                     "' cannot be opened for reading"));
      std::vector<Line> lines;
      std::string       text;
      for (unsigned int number = 1; std::getline(in, text); ++number)
        {
          const auto hash = text.find('#');
          if (hash != std::string::npos)
            text.erase(hash);
          std::istringstream words(text);
          Line               line{number, {}};
          std::string        word;
          while (words >> word)
            line.words.push_back(word);
          if (!line.words.empty())
            lines.push_back(line);
        }

      unsigned int current = 0;
      const auto   where   = [&](const unsigned int number) {
        return "patch file '" + filename + "', line " + std::to_string(number) +
               ": ";
      };
      const auto fail = [&](const unsigned int number,
                            const std::string &what) {
        AssertThrow(false, dealii::ExcMessage(where(number) + what));
      };
      const auto to_double = [&](const Line &line, const unsigned int i) {
        const std::string &word  = line.words[i];
        std::size_t        used  = 0;
        double             value = 0.;
        try
          {
            value = std::stod(word, &used);
          }
        catch (...)
          {
            used = 0;
          }
        if (used != word.size() || !std::isfinite(value))
          fail(line.number, "'" + word + "' is not a finite number");
        return value;
      };
      const auto to_unsigned = [&](const Line &line, const unsigned int i) {
        const double value = to_double(line, i);
        if (value < 0 || value != std::floor(value) || value > 1e9)
          fail(line.number,
               "'" + line.words[i] + "' is not a non-negative integer");
        return static_cast<unsigned int>(value);
      };
      // The next line, which must start with keyword and have n_values
      // values after it (n_values = -1: any number >= 1).
      const auto expect = [&](const std::string &keyword,
                              const int          n_values) -> const Line & {
        if (current >= lines.size())
          fail(lines.empty() ? 0 : lines.back().number,
               "the file ends where a '" + keyword + "' line is expected");
        const Line &line = lines[current++];
        if (line.words[0] != keyword)
          fail(line.number,
               "found '" + line.words[0] + "' where a '" + keyword +
                 "' line is expected");
        const int n = line.words.size() - 1;
        if ((n_values >= 0 && n != n_values) || (n_values < 0 && n < 1))
          fail(line.number,
               "'" + keyword + "' has " + std::to_string(n) +
                 " values; expected " +
                 (n_values >= 0 ? std::to_string(n_values) : "at least 1"));
        return line;
      };

      const Line &dimension_line = expect("dimension", 2);
      if (to_unsigned(dimension_line, 1) != dim ||
          to_unsigned(dimension_line, 2) != spacedim)
        fail(dimension_line.number,
             "dimension " + dimension_line.words[1] + " " +
               dimension_line.words[2] + " does not match the expected " +
               std::to_string(dim) + " " + std::to_string(spacedim));

      const Line                 &degree_line = expect("degrees", dim);
      std::array<KnotVector, dim> knot_vectors;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const unsigned int  degree = to_unsigned(degree_line, 1 + d);
          const Line         &line   = expect("knots", -1);
          std::vector<double> knots;
          for (unsigned int i = 1; i < line.words.size(); ++i)
            knots.push_back(to_double(line, i));
          try
            {
              knot_vectors[d] = KnotVector(knots, degree);
            }
          catch (const dealii::ExceptionBase &e)
            {
              fail(line.number,
                   "direction " + std::to_string(d) + ": " + exception_text(e));
            }
        }

      const Line        &count_line = expect("control_points", 1);
      const unsigned int n_points   = to_unsigned(count_line, 1);
      std::vector<dealii::Point<spacedim>> points(n_points);
      std::vector<double>                  weights(n_points);
      for (unsigned int a = 0; a < n_points; ++a)
        {
          if (current >= lines.size())
            fail(lines.back().number,
                 "the file ends after " + std::to_string(a) + " of " +
                   std::to_string(n_points) + " control points");
          const Line &line = lines[current++];
          if (line.words.size() != spacedim + 1)
            fail(line.number,
                 "control point " + std::to_string(a) + " has " +
                   std::to_string(line.words.size()) + " values; expected " +
                   std::to_string(spacedim + 1) + " (coordinates and weight)");
          for (unsigned int c = 0; c < spacedim; ++c)
            points[a][c] = to_double(line, c);
          weights[a] = to_double(line, spacedim);
          if (!(weights[a] > 0.))
            fail(line.number,
                 "weight " + std::to_string(a) + " (value " +
                   line.words[spacedim] +
                   ") is not allowed; weights must be positive and finite");
        }

      PatchGeometry<dim, spacedim> geometry;
      geometry.side_kinds.fill(SideKind::unspecified);
      try
        {
          geometry.patch =
            NURBSPatch<dim, spacedim>(knot_vectors, points, weights);
        }
      catch (const dealii::ExceptionBase &e)
        {
          fail(count_line.number, exception_text(e));
        }

      for (; current < lines.size(); ++current)
        {
          const Line &line = lines[current];
          if (line.words[0] == "side")
            {
              if (line.words.size() != 3)
                fail(line.number,
                     "'side' needs a side number and a kind (arc, symmetry, "
                     "straight)");
              const unsigned int f = to_unsigned(line, 1);
              if (f >= 2 * dim)
                fail(line.number,
                     "side " + line.words[1] +
                       " does not exist; sides are 0 "
                       "to " +
                       std::to_string(2 * dim - 1));
              try
                {
                  geometry.side_kinds[f] =
                    side_kind_names.from_string(line.words[2]);
                }
              catch (const dealii::ExceptionBase &e)
                {
                  fail(line.number, exception_text(e));
                }
            }
          else if (line.words[0] == "contact")
            {
              if (line.words.size() != dim + 1)
                fail(line.number,
                     "'contact' needs " + std::to_string(dim) +
                       " parameter values");
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double      value = to_double(line, 1 + d);
                  const KnotVector &kv    = geometry.patch.knot_vector(d);
                  if (value < kv.front() || value > kv.back())
                    fail(line.number,
                         "contact parameter " + line.words[1 + d] +
                           " lies outside [" + to_string(kv.front()) + ", " +
                           to_string(kv.back()) + "]");
                  geometry.contact_parameter[d] = value;
                }
              geometry.has_contact_point = true;
              geometry.contact_point =
                geometry.patch.evaluate(geometry.contact_parameter);
            }
          else
            fail(line.number,
                 "unknown keyword '" + line.words[0] +
                   "'; allowed after the control points are side and "
                   "contact");
        }
      return geometry;
    }



    template <int dim, int spacedim>
    void
    write_patch(const PatchGeometry<dim, spacedim> &geometry, std::ostream &out)
    {
      const auto &patch = geometry.patch;
      out.precision(17);
      out << "# isoimpact NURBS patch\n";
      out << "dimension " << dim << ' ' << spacedim << '\n';
      out << "degrees";
      for (unsigned int d = 0; d < dim; ++d)
        out << ' ' << patch.degree(d);
      out << '\n';
      for (unsigned int d = 0; d < dim; ++d)
        {
          out << "knots";
          for (const double k : patch.knot_vector(d).knots())
            out << ' ' << k;
          out << '\n';
        }
      out << "control_points " << patch.n_control_points()
          << "  # x y [z] weight\n";
      for (unsigned int a = 0; a < patch.n_control_points(); ++a)
        {
          for (unsigned int c = 0; c < spacedim; ++c)
            out << patch.control_points()[a][c] << ' ';
          out << patch.weights()[a] << '\n';
        }
      for (unsigned int f = 0; f < 2 * dim; ++f)
        if (geometry.side_kinds[f] != SideKind::unspecified)
          out << "side " << f << ' ' << to_string(geometry.side_kinds[f])
              << '\n';
      if (geometry.has_contact_point)
        {
          out << "contact";
          for (unsigned int d = 0; d < dim; ++d)
            out << ' ' << geometry.contact_parameter[d];
          out << '\n';
        }
    }



    template <int dim, int spacedim>
    void
    write_patch(const PatchGeometry<dim, spacedim> &geometry,
                const std::string                  &filename)
    {
      std::ofstream out(filename);
      AssertThrow(out.good(),
                  dealii::ExcMessage("patch file '" + filename +
                                     "' cannot be opened for writing"));
      write_patch(geometry, out);
      AssertThrow(out.good(),
                  dealii::ExcMessage("patch file '" + filename +
                                     "': writing failed"));
    }



#define ISOIMPACT_INSTANTIATE(dim, spacedim)                       \
  template struct PatchGeometry<dim, spacedim>;                    \
  template PatchGeometry<dim, spacedim> read_patch<dim, spacedim>( \
    const std::string &);                                          \
  template void write_patch<dim, spacedim>(                        \
    const PatchGeometry<dim, spacedim> &,                          \
    std::ostream &);                                               \
  template void write_patch<dim, spacedim>(                        \
    const PatchGeometry<dim, spacedim> &,                          \
    const std::string &);

    ISOIMPACT_INSTANTIATE(1, 1)
    ISOIMPACT_INSTANTIATE(1, 2)
    ISOIMPACT_INSTANTIATE(2, 2)
    ISOIMPACT_INSTANTIATE(2, 3)
    ISOIMPACT_INSTANTIATE(3, 3)
#undef ISOIMPACT_INSTANTIATE
  } // namespace nurbs
} // namespace isoimpact
