#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/deck.hpp"

using namespace pbx;

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

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
  EXPECT_NE(message_of([&] { m.positive("density", dim::density); }).find("m.density: must be > 0"),
            std::string::npos);
  EXPECT_NE(message_of([&] { m.quantity("shear_modulus", dim::pressure); }).find("m.shear_modulus: required"),
            std::string::npos);
  EXPECT_NE(message_of([&] { m.string("name"); }).find("expected a string"), std::string::npos);
}
