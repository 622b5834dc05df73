#pragma once
// One table of names per enumeration, beside the enumeration's to_string and parse: the text
// written to files and shown to users comes from it, parsing reads it back, and a parse error
// lists the valid names from the same table, so a new value is one row.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace tocd {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// The name of `value`; `fallback` for a value the table lacks (a corrupted value).
template <class E, std::size_t N>
constexpr std::string_view name_of(const std::array<EnumName<E>, N>& names, E value,
                                   std::string_view fallback = "unknown") noexcept {
  for (const auto& n : names)
    if (n.value == value) return n.name;
  return fallback;
}

/// The value named `name` exactly; none for another text.
template <class E, std::size_t N>
constexpr std::optional<E> value_of(const std::array<EnumName<E>, N>& names, std::string_view name) noexcept {
  for (const auto& n : names)
    if (n.name == name) return n.value;
  return std::nullopt;
}

/// The valid names for an error message: "a, b or c".
template <class E, std::size_t N>
std::string name_list(const std::array<EnumName<E>, N>& names) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    out += names[i].name;
  }
  return out;
}

}  // namespace tocd
