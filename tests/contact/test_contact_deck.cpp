// [contact] table: laws per material pair, same-material pairs across fields, and bad decks.
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "../deck_parts.hpp"
#include "../engine/scene_fixture.hpp"

using namespace pbx;
using ::testing::HasSubstr;

namespace {

// Binder field, two grain fields (colours) of one material.
std::string deck(const std::string& contact) {
  return R"(
[run]
end_time = "1 us"
[grid]
cell_size = "10 um"
min = ["0 mm", "0 mm"]
max = ["0.4 mm", "0.2 mm"]
[materials.tatb]
model = "linear_elastic"
density = "1.9 g/cm3"
youngs_modulus = "20 GPa"
poisson_ratio = 0.2
[materials.f2314]
model = "linear_elastic"
density = "2.0 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.4
)" + test::disk_mm(0.08, 0.1, 0.04, "tatb", "tatb_0") +
         test::disk_mm(0.18, 0.1, 0.04, "tatb", "tatb_1") + test::disk_mm(0.3, 0.1, 0.04, "f2314") + contact;
}

std::string error_of(const std::string& contact) {
  try {
    test::scene_from(deck(contact));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(ContactDeck, DefaultIsWeld) {
  Scene<2> sc = test::scene_from(deck(""));
  EXPECT_EQ(sc.contact.fields, 3);
  EXPECT_TRUE(sc.contact.all_weld());
}

TEST(ContactDeck, PairsByMaterialIncludingSameMaterialAcrossFields) {
  Scene<2> sc = test::scene_from(deck(R"(
[contact]
default = "frictionless"
normals = "average"
[[contact.pair]]
materials = ["f2314", "tatb"]
law = "coulomb"
friction = 0.3
[[contact.pair]]
materials = ["tatb", "tatb"]
law = "adhesion"
friction = 0.5
adhesion = "2 MPa"
)"));
  ASSERT_EQ(sc.contact.fields, 3);
  EXPECT_EQ(sc.contact.normal, ContactNormal::average);
  int f_t0 = -1, f_t1 = -1, f_b = -1;
  for (std::size_t f = 0; f < sc.field_names.size(); ++f) {
    if (sc.field_names[f] == "tatb_0") f_t0 = static_cast<int>(f);
    if (sc.field_names[f] == "tatb_1") f_t1 = static_cast<int>(f);
    if (sc.field_names[f] == "f2314") f_b = static_cast<int>(f);
  }
  ASSERT_GE(f_t0 + f_t1 + f_b, 3);
  EXPECT_EQ(sc.contact(f_t0, f_b).law, ContactLaw::coulomb);
  EXPECT_EQ(sc.contact(f_b, f_t1).law, ContactLaw::coulomb);
  EXPECT_DOUBLE_EQ(sc.contact(f_b, f_t1).friction, 0.3);
  EXPECT_EQ(sc.contact(f_t0, f_t1).law, ContactLaw::adhesion);
  EXPECT_DOUBLE_EQ(sc.contact(f_t1, f_t0).adhesion, 2e6);
  EXPECT_DOUBLE_EQ(sc.contact(f_t1, f_t0).friction, 0.5);
}

TEST(ContactDeck, BadDecksNameTheKey) {
  EXPECT_THAT(error_of("[contact]\n[[contact.pair]]\nmaterials = [\"tatb\", \"steel\"]\nlaw = \"frictionless\"\n"),
              AllOf(HasSubstr("contact.pair"), HasSubstr("materials"), HasSubstr("steel")));
  EXPECT_THAT(error_of("[contact]\ndefault = \"coulomb\"\nfriction = -0.1\n"),
              AllOf(HasSubstr("contact.friction"), HasSubstr(">= 0")));
  EXPECT_THAT(error_of("[contact]\n[[contact.pair]]\nmaterials = [\"tatb\", \"f2314\"]\nlaw = \"frictionless\"\n"
                       "[[contact.pair]]\nmaterials = [\"f2314\", \"tatb\"]\nlaw = \"coulomb\"\nfriction = 0.3\n"),
              AllOf(HasSubstr("materials"), HasSubstr("listed twice")));
  EXPECT_THAT(error_of("[contact]\ndefault = \"glue\"\n"), AllOf(HasSubstr("contact.default"), HasSubstr("glue")));
  EXPECT_THAT(error_of("[contact]\ndefault = \"coulomb\"\n"), HasSubstr("friction"));
  EXPECT_THAT(error_of("[contact]\ndefault = \"frictionless\"\nfriction = 0.2\n"), HasSubstr("takes no friction"));
  EXPECT_THAT(error_of("[contact]\nnormals = \"up\"\n"), HasSubstr("contact.normals"));
  EXPECT_THAT(error_of("[contact]\nposition_check = -1\n"), HasSubstr("contact.position_check"));
  EXPECT_THAT(error_of("[contact]\nfrobnicate = 1\n"), HasSubstr("frobnicate"));
  // binder_layer (contact/binder_layer.hpp)
  const std::string layer = "[contact]\n[[contact.pair]]\nmaterials = [\"tatb\", \"tatb\"]\nlaw = \"binder_layer\"\n";
  EXPECT_THAT(error_of("[contact]\ndefault = \"binder_layer\"\n"),
              AllOf(HasSubstr("contact.default"), HasSubstr("[[contact.pair]]")));
  EXPECT_THAT(error_of(layer + "binder = \"f2314\"\nthickness = \"2 um\"\n"), HasSubstr("friction"));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nnormal_stiffness = 1e15\nbinder = \"f2314\"\n"),
              AllOf(HasSubstr("binder"), HasSubstr("not both")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"glue\"\nthickness = \"2 um\"\n"),
              AllOf(HasSubstr("contact.pair"), HasSubstr("binder"), HasSubstr("no material named 'glue'")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nclosure = 1.5\n"),
              HasSubstr("closure"));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"-2 um\"\n"), HasSubstr("thickness"));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nshear_cap = \"tresca\"\n"),
              AllOf(HasSubstr("shear_cap"), HasSubstr("'coulomb' or 'none'")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\ncoat_scale = 2\n"),
              AllOf(HasSubstr("coat_scale"), HasSubstr("coats")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"coats\"\ncoat_scale = 0\n"),
              HasSubstr("coat_scale"));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nfilm = \"bonded\"\n"),
              AllOf(HasSubstr("film"), HasSubstr("'uniform', 'integrated' or 'bonds'")));
  // film = "bonds": film flow is not built for its pairs, and direct stiffnesses per area do not make
  // a pair's spring (a film takes binder and thickness); both refused naming the key
  EXPECT_THAT(error_of(layer + "friction = 0.3\nnormal_stiffness = 1e15\nshear_stiffness = 1e14\nfilm = \"bonds\"\n"),
              AllOf(HasSubstr("film"), HasSubstr("binder and thickness, not both")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nfilm = \"bonds\"\n"
                               "flow_factor = 0.5\n"),
              AllOf(HasSubstr("flow_factor"), HasSubstr("film = \"bonds\"")));
  EXPECT_THAT(
      error_of(
          layer +
          "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nflow_stress = \"10 MPa\"\nflow_factor = 0.5\n"),
      AllOf(HasSubstr("flow_factor"), HasSubstr("not both")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nflow_factor = -0.5\n"),
              AllOf(HasSubstr("flow_factor"), HasSubstr("> 0")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nflow_stress = \"-1 MPa\"\n"),
              HasSubstr("flow_stress"));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nnormal_stiffness = 1e15\nshear_stiffness = 1e14\nflow_factor = 0.5\n"),
              AllOf(HasSubstr("flow_factor"), HasSubstr("shear modulus")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nfilm_extent = 3\n"),
              AllOf(HasSubstr("film_extent"), HasSubstr("integrated")));
  EXPECT_THAT(
      error_of(layer +
               "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nfilm = \"integrated\"\nfilm_extent = -1\n"),
      HasSubstr("film_extent"));
  EXPECT_THAT(
      error_of(
          layer +
          "friction = 0.3\nbinder = \"f2314\"\nthickness = \"2 um\"\nfilm = \"integrated\"\nbond_gap = \"2 um\"\n"),
      AllOf(HasSubstr("bond_gap"), HasSubstr("integrated")));
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"coat\"\n"), HasSubstr("thickness"));
  // the disks here are [[geometry]], not a packing: no coats to take the thickness from
  EXPECT_THAT(error_of(layer + "friction = 0.3\nbinder = \"f2314\"\nthickness = \"coats\"\n"),
              AllOf(HasSubstr("contact.pair"), HasSubstr("packed specimen")));
}
