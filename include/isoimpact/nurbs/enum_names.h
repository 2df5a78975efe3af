// The names of an enumeration's values from one table: to_string,
// from_string and the list of a ParameterHandler selection. In layer 1, the
// lowest that names an enumeration (nurbs::SideKind); used by all layers.
#ifndef isoimpact_nurbs_enum_names_h
#define isoimpact_nurbs_enum_names_h

#include <deal.II/base/exceptions.h>

#include <array>
#include <cstddef>
#include <string>
#include <utility>

namespace isoimpact
{
  /**
   * The table of an enumeration's names, for example
   *   inline constexpr EnumNames<MassScheme, 3> mass_scheme_names{
   *     "mass matrix",
   *     {{{MassScheme::consistent, "consistent"}, ...}}};
   * `what` names the enumeration in error messages.
   */
  template <typename Enum, std::size_t N>
  struct EnumNames
  {
    const char                                  *what;
    std::array<std::pair<Enum, const char *>, N> names;

    // The name of `value`.
    std::string
    to_string(const Enum value) const
    {
      for (const auto &[entry, name] : names)
        if (entry == value)
          return name;
      AssertThrow(false,
                  dealii::ExcMessage(std::string(what) +
                                     ": a value without a name in the table"));
      return "";
    }

    // The value named `name` (exact spelling); throws, listing the allowed
    // names, for any other text.
    Enum
    from_string(const std::string &name) const
    {
      for (const auto &[entry, entry_name] : names)
        if (name == entry_name)
          return entry;
      AssertThrow(false,
                  dealii::ExcMessage(std::string(what) + " '" + name +
                                     "' is unknown; allowed: " + allowed()));
      return names[0].first;
    }

    // The names quoted and separated by commas: "a", "b".
    std::string
    allowed() const
    {
      return joined("\", \"", "\"");
    }

    // The names separated by '|', the list of a dealii::Patterns::Selection.
    std::string
    selection() const
    {
      return joined("|", "");
    }

  private:
    std::string
    joined(const std::string &separator, const std::string &quote) const
    {
      std::string text = quote;
      for (std::size_t i = 0; i < N; ++i)
        text += (i > 0 ? separator : "") + names[i].second;
      return text + quote;
    }
  };
} // namespace isoimpact

#endif
