#pragma once
// Names of enum values, from one table per enum: the name written in CSV comments, settings and
// command lines, the value parsed back from it, and the list of values for menus and loops.
//
//   constexpr motionmap::EnumName<Axis> kAxes[] = {{Axis::Y, "y"}, {Axis::Z, "z"}};
//   enum_name(kAxes, Axis::Z)      // "z"
//   parse_enum(kAxes, "y")         // Axis::Y
//   enum_values(kAxes)             // {Axis::Y, Axis::Z}
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace motionmap {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of `value` in `table`; "?" for a value the table does not hold.
template <class E, std::size_t N>
constexpr std::string_view enum_name(const EnumName<E> (&table)[N], E value) {
  for (const EnumName<E>& e : table) {
    if (e.value == value) return e.name;
  }
  return "?";
}

/// The value named exactly `name` (as enum_name writes it); nullopt for any other text.
template <class E, std::size_t N>
constexpr std::optional<E> parse_enum(const EnumName<E> (&table)[N], std::string_view name) {
  for (const EnumName<E>& e : table) {
    if (e.name == name) return e.value;
  }
  return std::nullopt;
}

/// Every value of `table`, in its order.
template <class E, std::size_t N>
std::vector<E> enum_values(const EnumName<E> (&table)[N]) {
  std::vector<E> values;
  for (const EnumName<E>& e : table) values.push_back(e.value);
  return values;
}

}  // namespace motionmap
