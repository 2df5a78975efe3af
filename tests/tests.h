// Small test helpers: every check prints the value, the expected value and
// the tolerance, and a failed check makes the program exit non-zero.
#ifndef isoimpact_tests_h
#define isoimpact_tests_h

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace isoimpact_tests
{
  inline int &
  failures()
  {
    static int n = 0;
    return n;
  }

  inline int &
  checks()
  {
    static int n = 0;
    return n;
  }

  // The failed checks' lines, repeated by report() at the end: a log cut to
  // its last lines (CI's) still names them.
  inline std::vector<std::string> &
  failed_lines()
  {
    static std::vector<std::string> lines;
    return lines;
  }

  // Relative check |value - expected| <= tolerance * |expected|, or with
  // absolute = true, |value - expected| <= absolute_tolerance.
  inline bool
  check_close(const std::string &what,
              const double       value,
              const double       expected,
              const double       relative_tolerance,
              const double       absolute_tolerance = 0.,
              const bool         absolute           = false)
  {
    ++checks();
    const double scale = absolute ? absolute_tolerance : std::abs(expected);
    const double error = std::abs(value - expected);
    const bool ok = std::isfinite(value) && error <= relative_tolerance * scale;
    std::ostringstream line;
    line << (ok ? "ok   " : "FAIL ") << what << ": " << std::setprecision(12)
         << value << " expected " << expected << " (error "
         << std::setprecision(3) << error << ", allowed "
         << relative_tolerance * scale << ")";
    std::cout << line.str() << std::endl;
    if (!ok)
      {
        ++failures();
        failed_lines().push_back(line.str());
      }
    return ok;
  }

  inline bool
  check_true(const std::string &what, const bool condition)
  {
    ++checks();
    std::cout << (condition ? "ok   " : "FAIL ") << what << std::endl;
    if (!condition)
      {
        ++failures();
        failed_lines().push_back("FAIL " + what);
      }
    return condition;
  }

  // Returns the exit code of a test program.
  inline int
  report()
  {
    if (!failed_lines().empty())
      std::cout << "failed checks, again:" << std::endl;
    for (const auto &line : failed_lines())
      std::cout << line << std::endl;
    std::cout << checks() - failures() << " passed, " << failures() << " failed"
              << std::endl;
    return failures() == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
  }
} // namespace isoimpact_tests

#define CHECK_CLOSE(value, expected, tolerance) \
  isoimpact_tests::check_close(#value, (value), (expected), (tolerance))
#define CHECK_CLOSE_ABS(value, expected, tolerance) \
  isoimpact_tests::check_close(#value,              \
                               (value),             \
                               (expected),          \
                               1.,                  \
                               (tolerance),         \
                               true)
#define CHECK_TRUE(condition) \
  isoimpact_tests::check_true(#condition, (condition))

#endif
