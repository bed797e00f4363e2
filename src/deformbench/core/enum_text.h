#pragma once
//! The text of an enum, in one table per enum: each enum E declares `const EnumText<E>& enum_text(E)` beside it
//! (found by argument-dependent lookup), and the printer, the parser, the list of names a command line offers and
//! the docs all read that table.
//!
//!   enum class Weights { Uniform, Cotan };
//!   const EnumText<Weights>& enum_text(Weights);   // {"weights", {{Weights::Uniform, "uniform"}, ...}}
//!   to_string(Weights::Cotan) == "cotan";  parse_enum<Weights>("cotan") == Weights::Cotan;
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

template <class E>
struct EnumText {
  const char* what;                              //!< the noun of an error message ("build", "frame mode")
  std::vector<std::pair<E, const char*>> names;  //!< every value once, in the order help texts list them
};

//! The names of E's values in table order.
template <class E>
std::vector<std::string> enum_names() {
  std::vector<std::string> out;
  for (const auto& [value, text] : enum_text(E{}).names) out.emplace_back(text);
  return out;
}

//! "a, b or c": the names as an error message lists them.
template <class E>
std::string enum_choices() {
  const std::vector<std::string> n = enum_names<E>();
  std::string s;
  for (std::size_t i = 0; i < n.size(); ++i) s += (i == 0 ? "" : i + 1 == n.size() ? " or " : ", ") + n[i];
  return s;
}

//! The value named `s`. \throw InputError "unknown build 'x' (expected dense, naive or structured)".
template <class E>
E parse_enum(const std::string& s) {
  for (const auto& [value, text] : enum_text(E{}).names)
    if (s == text) return value;
  throw InputError(fmt::format("unknown {} '{}' (expected {})", enum_text(E{}).what, s, enum_choices<E>()));
}

//! The name of `e` ("?" for a value outside the table, which a complete table never gives).
template <class E, class = decltype(enum_text(std::declval<E>()))>
std::string to_string(E e) {
  for (const auto& [value, text] : enum_text(e).names)
    if (value == e) return text;
  return "?";
}

//! Prints the name (test messages, logs).
template <class E, class = decltype(enum_text(std::declval<E>()))>
std::ostream& operator<<(std::ostream& os, E e) {
  return os << to_string(e);
}

}  // namespace db
