// Numeric options refuse what CLI11 alone would wrap, read as octal or pass through as NaN,
// and name the value and the accepted range.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "numeric_options.hpp"

namespace cli = tocd::cli;

namespace {

struct Values {
  std::uint64_t photons = 7, seed = 3;
  int threads = 1;
  double size = 1.0, free = 0.0;
  std::optional<double> index;
  std::vector<double> list;
};

// Builds an app with ranged and unranged options, parses `args`, returns the error ("" if none).
std::string parse(Values& v, std::vector<std::string> args) {
  CLI::App app;
  auto* sub = app.add_subcommand("run");
  sub->add_option("--photons", v.photons)->check(cli::whole_in(std::uint64_t{1}, cli::kMaxPhotons));
  sub->add_option("--seed", v.seed);  // no explicit range: the type's range applies
  sub->add_option("--threads", v.threads)
      ->check(cli::whole_in(std::int64_t{0}, std::int64_t{cli::kMaxThreads}));
  sub->add_option("--size", v.size)->check(cli::real_above(0.0, 100.0));
  sub->add_option("--free", v.free);
  sub->add_option("--index", v.index)->check(cli::real_in(1.0, 5.0));
  sub->add_option("--list", v.list)->check(cli::real_in(0.0, 10.0))->delimiter(',');
  cli::check_numeric_syntax(app);
  args.insert(args.begin(), "run");
  std::vector<const char*> argv{"prog"};
  for (const auto& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(NumericOptions, NegativeUnsignedIsRefusedWithTheRange) {
  Values v;
  EXPECT_EQ(parse(v, {"--photons", "-5"}), "--photons: -5 is out of range: accepted 1 to 1000000000000");
  EXPECT_EQ(v.photons, 7u);
  EXPECT_EQ(parse(v, {"--seed", "-1"}), "--seed: -1 is out of range: accepted 0 to 18446744073709551615");
  EXPECT_EQ(parse(v, {"--photons", "0"}), "--photons: 0 is out of range: accepted 1 to 1000000000000");
  EXPECT_EQ(parse(v, {"--photons", "1000000000001"}),
            "--photons: 1000000000001 is out of range: accepted 1 to 1000000000000");
  EXPECT_EQ(parse(v, {"--seed", "18446744073709551616"}),
            "--seed: 18446744073709551616 is out of range: accepted 0 to 18446744073709551615");
}

TEST(NumericOptions, WholeNumbersAreDecimalOnly) {
  Values v;
  EXPECT_EQ(parse(v, {"--photons", "010", "--seed", "0010"}), "");
  EXPECT_EQ(v.photons, 10u);  // CLI11 alone reads 010 as octal 8
  EXPECT_EQ(v.seed, 10u);
  EXPECT_EQ(parse(v, {"--seed", "0x10"}), "--seed: '0x10' is not a whole number (decimal digits only)");
  EXPECT_EQ(parse(v, {"--photons", "1e6"}), "--photons: '1e6' is not a whole number (decimal digits only)");
  EXPECT_EQ(parse(v, {"--threads", "-1"}), "--threads: -1 is out of range: accepted 0 to 1024");
  EXPECT_EQ(parse(v, {"--threads", "4"}), "");
  EXPECT_EQ(v.threads, 4);
}

TEST(NumericOptions, RealsMustBeFiniteAndInRange) {
  Values v;
  EXPECT_EQ(parse(v, {"--size", "nan"}), "--size: nan is out of range: accepted above 0 up to 100");
  EXPECT_EQ(parse(v, {"--size", "0"}), "--size: 0 is out of range: accepted above 0 up to 100");
  EXPECT_EQ(parse(v, {"--size", "100"}), "");
  EXPECT_DOUBLE_EQ(v.size, 100.0);
  EXPECT_EQ(parse(v, {"--size", "1e400"}), "--size: 1e400 is out of range: accepted above 0 up to 100");
  EXPECT_EQ(parse(v, {"--size", "abc"}), "--size: 'abc' is not a number");
  // Unranged reals still refuse NaN and infinities.
  EXPECT_NE(parse(v, {"--free", "inf"}).find("--free: inf is out of range"), std::string::npos);
  EXPECT_NE(parse(v, {"--free", "-nan"}).find("--free: -nan is out of range"), std::string::npos);
  EXPECT_EQ(parse(v, {"--free", "-3.5"}), "");
  EXPECT_DOUBLE_EQ(v.free, -3.5);
  EXPECT_EQ(parse(v, {"--index", "0.5"}), "--index: 0.5 is out of range: accepted from 1 up to 5");
  EXPECT_EQ(parse(v, {"--index", "1.33"}), "");
  ASSERT_TRUE(v.index.has_value());
  EXPECT_DOUBLE_EQ(*v.index, 1.33);
}

TEST(NumericOptions, EachListElementIsChecked) {
  Values v;
  EXPECT_EQ(parse(v, {"--list", "1,2.5,10"}), "");
  EXPECT_EQ(v.list, (std::vector<double>{1, 2.5, 10}));
  EXPECT_EQ(parse(v, {"--list", "1,nan,3"}), "--list: nan is out of range: accepted from 0 up to 10");
}
