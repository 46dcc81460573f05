#include <gtest/gtest.h>

#include "input_error_message.hpp"

#include "core/error.hpp"
#include "io/deck.hpp"

using namespace pbx;

using pbx::test::message_of;

TEST(Deck, ReadsQuantitiesAndReportsUnknownKeysWithLine) {
  auto deck = Deck::from_string("[grid]\ncell_size = \"5 um\"\ncfll = 0.5\n", "d.toml");
  auto g = deck.root().table("grid");
  EXPECT_NEAR(g.quantity("cell_size", dim::length), 5e-6, 1e-18);
  auto msg = message_of([&] { deck.check_unused(); });
  EXPECT_NE(msg.find("unknown key 'grid.cfll'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("d.toml:3"), std::string::npos) << msg;
}

TEST(Deck, NamesMissingAndNonPhysicalKeys) {
  auto deck = Deck::from_string("[m]\ndensity = -3.0\nname = 4\n", "d.toml");
  auto m = deck.root().table("m");
  EXPECT_NE(message_of([&] { m.positive("density", dim::density); }).find("m.density: must be > 0"), std::string::npos);
  EXPECT_NE(message_of([&] { m.quantity("shear_modulus", dim::pressure); }).find("m.shear_modulus: required"),
            std::string::npos);
  EXPECT_NE(message_of([&] { m.string("name"); }).find("expected a string"), std::string::npos);
}

// A plain density below 100 kg/m^3 is read as SI but stated on stderr (g/cm3 without its unit is
// the likely slip); the same value with a unit, or a real SI density, says nothing.
TEST(Deck, PlainDensityThatLooksLikeGramsPerCm3IsStated) {
  auto deck = Deck::from_string("[m]\na = 1.934\nb = \"1.934 g/cm3\"\nc = 1934.0\n", "d.toml");
  auto m = deck.root().table("m");
  testing::internal::CaptureStderr();
  EXPECT_DOUBLE_EQ(m.positive("a", dim::density), 1.934);
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("d.toml:2: m.a: the plain number 1.934 is read as 1.934 kg/m^3"), std::string::npos) << err;
  EXPECT_NE(err.find("\"1.934 g/cm3\""), std::string::npos) << err;
  testing::internal::CaptureStderr();
  EXPECT_NEAR(m.positive("b", dim::density), 1934.0, 1e-9);
  EXPECT_DOUBLE_EQ(m.positive("c", dim::density), 1934.0);
  err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "");
}
