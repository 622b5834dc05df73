// The one name table per enumeration (tocd/core/enum_names.hpp): names out, values back, the
// list an error shows.
#include <gtest/gtest.h>

#include "tocd/core/enum_names.hpp"

namespace {

enum class Colour { red, green, blue, violet };
constexpr std::array<tocd::EnumName<Colour>, 3> kColourNames{
    {{Colour::red, "red"}, {Colour::green, "green"}, {Colour::blue, "blue"}}};

TEST(EnumNames, EveryValueReadsBackFromItsName) {
  for (const auto& n : kColourNames) {
    EXPECT_EQ(tocd::name_of(kColourNames, n.value), n.name);
    ASSERT_TRUE(tocd::value_of(kColourNames, n.name).has_value());
    EXPECT_EQ(*tocd::value_of(kColourNames, n.name), n.value);
  }
}

TEST(EnumNames, UnknownTextAndValuesAreSaidSo) {
  EXPECT_FALSE(tocd::value_of(kColourNames, "Red").has_value());  // exact names only
  EXPECT_FALSE(tocd::value_of(kColourNames, "").has_value());
  EXPECT_EQ(tocd::name_of(kColourNames, Colour::violet), "unknown");
  EXPECT_EQ(tocd::name_of(kColourNames, Colour::violet, "?"), "?");
}

TEST(EnumNames, TheListOfValidNamesReadsAsASentence) {
  EXPECT_EQ(tocd::name_list(kColourNames), "red, green or blue");
  constexpr std::array<tocd::EnumName<Colour>, 1> one{{{Colour::red, "red"}}};
  EXPECT_EQ(tocd::name_list(one), "red");
  constexpr std::array<tocd::EnumName<Colour>, 2> two{{{Colour::red, "red"}, {Colour::blue, "blue"}}};
  EXPECT_EQ(tocd::name_list(two), "red or blue");
}

// Resolved at compile time: a table can serve constant expressions.
static_assert(tocd::name_of(kColourNames, Colour::green) == "green");
static_assert(*tocd::value_of(kColourNames, "blue") == Colour::blue);

}  // namespace
