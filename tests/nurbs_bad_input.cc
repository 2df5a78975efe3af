// Every validation rule of the NURBS layer throws a message that names the
// offending value; patch files round-trip and their errors name file and line.
#include <isoimpact/nurbs/geometries.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "tests.h"

using namespace dealii;

using namespace isoimpact::nurbs;
using dealii::Point;

namespace
{
  // Runs f, expects a dealii::ExceptionBase whose what() contains all texts.
  void
  expect_error(const std::string              &name,
               const std::function<void()>    &f,
               const std::vector<std::string> &texts)
  {
    std::string message;
    try
      {
        f();
      }
    catch (const dealii::ExceptionBase &e)
      {
        // deal.II wraps long messages: compare with single spaces.
        std::istringstream words(e.what());
        std::string        word;
        while (words >> word)
          message += word + " ";
      }
    bool found = !message.empty();
    for (const auto &text : texts)
      found = found && message.find(text) != std::string::npos;
    isoimpact_tests::check_true(name + " -> error containing '" + texts[0] +
                                  "'",
                                found);
    if (!found)
      std::cout << "     message was: " << message << std::endl;
  }

  void
  write_file(const std::string &filename, const std::string &text)
  {
    std::ofstream out(filename);
    out << text;
  }

  const std::string good_header = "dimension 1 2\n"
                                  "degrees 2\n"
                                  "knots 0 0 0 1 1 1\n";
} // namespace

int
main()
{
  // Knot vectors.
  expect_error("decreasing knots",
               [] {
                 KnotVector({0, 0, 0, 0.5, 0.2, 1, 1, 1}, 2);
               },
               {"knot 4 (value 0.2) is smaller than knot 3 (value 0.5)",
                "non-decreasing"});
  expect_error("first value multiplicity 2 for p = 2",
               [] {
                 KnotVector({0, 0, 0.5, 1, 1, 1}, 2);
               },
               {"first knot value 0 has multiplicity 2", "exactly 3"});
  expect_error("last value multiplicity 4 for p = 2",
               [] {
                 KnotVector({0, 0, 0, 0.5, 1, 1, 1, 1}, 2);
               },
               {"last knot value 1 has multiplicity 4", "exactly 3"});
  expect_error("unequal end values",
               [] {
                 KnotVector({0, 0, 0.1, 0.5, 1, 1, 1}, 2);
               },
               {"first knot value 0 has multiplicity 2"});
  expect_error("interior multiplicity 3 for p = 2",
               [] {
                 KnotVector({0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, 2);
               },
               {"interior knot value 0.5 has multiplicity 3", "at most"});
  expect_error("degree 0",
               [] {
                 KnotVector({0, 1}, 0);
               },
               {"degree 0", "at least 1"});
  expect_error("no non-empty span",
               [] {
                 KnotVector({2, 2, 2, 2, 2, 2}, 2);
               },
               {"first and last knot are both 2", "non-empty"});
  expect_error("too few knots",
               [] {
                 KnotVector({0, 0, 1, 1}, 2);
               },
               {"4 knots given for degree 2", "at least"});
  expect_error("NaN knot",
               [] {
                 KnotVector({0, 0, 0, std::nan(""), 1, 1, 1}, 2);
               },
               {"knot 3 (value nan)", "finite"});
  expect_error("parameter outside",
               [] {
                 KnotVector::uniform(2, 2).span_of(1.5);
               },
               {"parameter 1.5 lies outside", "[0, 1]"});
  expect_error("insert end knot",
               [] {
                 KnotVector::uniform(2, 2).insert_knot(1.);
               },
               {"value 1 is not strictly inside"});
  expect_error("insertion beyond multiplicity p",
               [] {
                 KnotVector::uniform(2, 2).insert_knot(0.5, 2);
               },
               {"value 0.5 would get multiplicity 3"});

  // Patches.
  const KnotVector            kv = KnotVector::uniform(2, 1);
  const std::vector<Point<2>> nine(9);
  expect_error("wrong number of control points",
               [&] {
                 NURBSPatch<2>({{kv, kv}}, std::vector<Point<2>>(8));
               },
               {"8 control points given", "3 x 3 = 9"});
  expect_error("wrong number of weights",
               [&] {
                 NURBSPatch<2>({{kv, kv}}, nine, std::vector<double>(10, 1.));
               },
               {"10 weights given"});
  std::vector<double> weights(9, 1.);
  weights[4] = -0.5;
  expect_error("negative weight",
               [&] {
                 NURBSPatch<2>({{kv, kv}}, nine, weights);
               },
               {"weight 4 (value -0.5)", "positive and finite"});
  weights[4] = 0.;
  expect_error("zero weight",
               [&] {
                 NURBSPatch<2>({{kv, kv}}, nine, weights);
               },
               {"weight 4 (value 0)"});
  weights[4] = std::numeric_limits<double>::infinity();
  expect_error("infinite weight",
               [&] {
                 NURBSPatch<2>({{kv, kv}}, nine, weights);
               },
               {"weight 4 (value inf)"});
  expect_error("bad radius",
               [] {
                 half_disk(-2., Point<2>());
               },
               {"radius -2", "positive"});
  expect_error("annulus radii",
               [] {
                 quarter_annulus(2., 1.);
               },
               {"inner radius 2 is not smaller than outer radius 1"});
  expect_error("bad grading ratio",
               [] {
                 half_disk(1.).patch.refine_graded(0, 0, 2, -1.);
               },
               {"grading ratio -1"});

  // Patch files: round trip of the half disk.
  {
    auto geometry = half_disk(0.5, Point<2>(1., 2.));
    geometry.patch.refine_uniformly(2);
    write_patch(geometry, "nurbs_half_disk.patch");
    const auto read = read_patch<2>("nurbs_half_disk.patch");
    CHECK_TRUE(read.patch.n_elements() == 4);
    CHECK_TRUE(read.side_kinds == geometry.side_kinds);
    CHECK_TRUE(read.has_contact_point);
    CHECK_CLOSE_ABS(read.contact_point.distance(Point<2>(1., 1.5)), 0., 1e-15);
    double max_difference = 0.;
    for (unsigned int i = 0; i <= 10; ++i)
      for (unsigned int j = 0; j <= 10; ++j)
        max_difference =
          std::max(max_difference,
                   read.patch.evaluate(Point<2>(0.1 * i, 0.1 * j))
                     .distance(
                       geometry.patch.evaluate(Point<2>(0.1 * i, 0.1 * j))));
    CHECK_CLOSE_ABS(max_difference, 0., 1e-15);
  }

  // Patch file errors.
  expect_error("missing file",
               [] {
                 read_patch<2>("no_such_file.patch");
               },
               {"patch file 'no_such_file.patch' cannot be opened"});
  write_file("bad1.patch",
             good_header + "control_points 3\n0 0 1\n1 0\n2 0 1\n");
  expect_error("control point with missing weight",
               [] {
                 read_patch<1, 2>("bad1.patch");
               },
               {"patch file 'bad1.patch', line 6",
                "control point 1 has 2 values"});
  write_file("bad2.patch",
             "# comment line\n" + good_header +
               "control_points 3\n0 0 1\n1 0 -1\n2 0 1\n");
  expect_error("negative weight in file",
               [] {
                 read_patch<1, 2>("bad2.patch");
               },
               {"patch file 'bad2.patch', line 7", "weight 1 (value -1)"});
  write_file("bad3.patch",
             "dimension 1 2\ndegrees 2\nknots 0 0 0 0.7 0.5 1 1 1\n");
  expect_error("bad knots in file",
               [] {
                 read_patch<1, 2>("bad3.patch");
               },
               {"patch file 'bad3.patch', line 3",
                "knot 4 (value 0.5) is smaller than knot 3 (value 0.7)"});
  write_file("bad4.patch",
             good_header + "control_points 3\n0 0 1\n1 zero 1\n2 0 1\n");
  expect_error("not a number",
               [] {
                 read_patch<1, 2>("bad4.patch");
               },
               {"patch file 'bad4.patch', line 6",
                "'zero' is not a finite number"});
  write_file("bad5.patch", good_header);
  expect_error("dimension mismatch",
               [] {
                 read_patch<2, 2>("bad5.patch");
               },
               {"patch file 'bad5.patch', line 1",
                "dimension 1 2 does not match"});
  write_file("bad6.patch",
             good_header +
               "control_points 3\n0 0 1\n1 0 1\n2 0 1\nside 1 round\n");
  expect_error("unknown side kind",
               [] {
                 read_patch<1, 2>("bad6.patch");
               },
               {"patch file 'bad6.patch', line 8",
                "side kind 'round' is unknown"});
  write_file("bad7.patch", good_header + "control_points 3\n0 0 1\n1 0 1\n");
  expect_error("too few control points",
               [] {
                 read_patch<1, 2>("bad7.patch");
               },
               {"patch file 'bad7.patch'", "ends after 2 of 3 control points"});
  for (const char *name : {"bad1.patch",
                           "bad2.patch",
                           "bad3.patch",
                           "bad4.patch",
                           "bad5.patch",
                           "bad6.patch",
                           "bad7.patch"})
    std::remove(name);
  return isoimpact_tests::report();
}
