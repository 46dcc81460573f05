#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/units.hpp"

using namespace pbx;

TEST(Units, ConvertsCommonQuantitiesToSI) {
  EXPECT_DOUBLE_EQ(to_si("11.5 GPa", dim::pressure, "G"), 11.5e9);
  EXPECT_NEAR(to_si("1.934 g/cm3", dim::density, "rho"), 1934.0, 1e-9);
  EXPECT_NEAR(to_si("5 um", dim::length, "h"), 5e-6, 1e-18);
  EXPECT_DOUBLE_EQ(to_si("0.3 m/s", dim::velocity, "v"), 0.3);
  EXPECT_DOUBLE_EQ(to_si("100 kJ/mol", dim::molar_energy, "Ea"), 1e5);
  EXPECT_DOUBLE_EQ(to_si("250 1/s", dim::rate, "rate"), 250.0);
  EXPECT_DOUBLE_EQ(to_si("4e-3 /K", dim::per_temperature, "B1"), 4e-3);
  EXPECT_DOUBLE_EQ(to_si("293 K", dim::temperature, "T"), 293.0);
  EXPECT_NEAR(to_si("2.02 g/cm^3", dim::density, "rho"), 2020.0, 1e-9);
}

TEST(Units, RejectsWrongDimensionAndUnknownUnits) {
  EXPECT_THROW(to_si("11.5 GPa", dim::density, "rho"), InputError);
  EXPECT_THROW(to_si("3 furlongs", dim::length, "x"), InputError);
  EXPECT_THROW(to_si("GPa", dim::pressure, "x"), InputError);
  try {
    to_si("1 m/s", dim::pressure, "materials.tatb.shear_modulus");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("materials.tatb.shear_modulus"), std::string::npos);
  }
}
