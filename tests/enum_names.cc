// EnumNames, the one table of names behind every enumerated parameter:
// - each table's selection list is the spelling of the parameter files and
//   patch files (the literal lists the parameter patterns had before);
// - from_string(to_string(v)) == v for every value of every table;
// - an unknown name throws a message naming the enumeration, the text and
//   the allowed names.
#include <isoimpact/mechanics/assembly.h>
#include <isoimpact/mechanics/contact.h>
#include <isoimpact/nurbs/geometries.h>
#include <isoimpact/scene/hertz_reference.h>

#include <exception>
#include <sstream>
#include <string>

#include "tests.h"

using namespace isoimpact;

namespace
{
  template <typename Table>
  void
  check_table(const Table &table, const std::string &expected_selection)
  {
    const std::string what(table.what);
    isoimpact_tests::check_true(what + ": selection '" + table.selection() +
                                  "'",
                                table.selection() == expected_selection);
    unsigned int round_trips = 0;
    for (const auto &entry : table.names)
      if (table.from_string(table.to_string(entry.first)) == entry.first)
        ++round_trips;
    isoimpact_tests::check_close(what + ": values that survive the round trip",
                                 round_trips,
                                 table.names.size(),
                                 0.);
  }

  // The message of from_string(name), whitespace runs collapsed (deal.II
  // wraps long messages); empty if it does not throw.
  std::string
  message_of_unknown(const EnumNames<MassScheme, 3> &table,
                     const std::string              &name)
  {
    try
      {
        table.from_string(name);
      }
    catch (const std::exception &exception)
      {
        std::istringstream words(exception.what());
        std::string        word, message;
        while (words >> word)
          message += (message.empty() ? "" : " ") + word;
        return message;
      }
    return "";
  }
} // namespace

int
main()
{
  check_table(nurbs::side_kind_names, "arc|symmetry|straight|unspecified");
  check_table(fea_element_names, "lagrange|serendipity");
  check_table(mass_scheme_names, "consistent|row-sum|HRZ");
  check_table(penalty_per_pass_names, "half|full");
  check_table(approach_law_names, "Gerl-Zippelius|Johnson");

  CHECK_TRUE(to_string(MassScheme::row_sum) == "row-sum" &&
             to_string(nurbs::SideKind::unspecified) == "unspecified");
  // Names are exact: no case folding, no trimming.
  const std::string message = message_of_unknown(mass_scheme_names, "hrz");
  std::cout << message << std::endl;
  CHECK_TRUE(message.find("mass matrix 'hrz' is unknown; allowed: "
                          "\"consistent\", \"row-sum\", \"HRZ\"") !=
             std::string::npos);
  CHECK_TRUE(message_of_unknown(mass_scheme_names, " HRZ") != "");
  return isoimpact_tests::report();
}
