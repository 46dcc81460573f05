// A contact law added by one registration call (contact/law_registry.hpp, docs/extending.md): a toy
// "partial weld" that gives field a the fraction phi of the stick impulse, d = phi (m_a p_r - m_r
// p_a)/(m_a + m_r), read from a deck by its name with its own key. Against closed forms: at one node
// the impulse is exactly phi x stick; on the two colliding disks (two_disks_deck.hpp) phi = 1 is the
// built-in weld, history for history to round-off, and phi = 0 lets the disks pass through each other
// with each disk's momentum unchanged (no exchange at all). Bad input names the key; a taken name is
// refused at registration.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "../engine/scene_fixture.hpp"
#include "contact/field_contact.hpp"
#include "contact/law_registry.hpp"
#include "core/error.hpp"
#include "two_disks_deck.hpp"

using namespace pbx;

namespace {

struct PartialWeld {
  static constexpr bool needs_normal = false;
  double fraction = 1;
  template <int D>
  Exchange<D> exchange(const NodeContact<D>& c) const {
    Exchange<D> e;
    e.acts = fraction > 0.0;
    e.d = fraction * c.stick;
    return e;
  }
};

// Registered once per process (the registry refuses a second registration of a name).
void register_toy() {
  static const bool done = [] {
    register_contact_law<PartialWeld>("toy_partial_weld", [](const ParamTable& t) {
      const double f = t.number("fraction");
      if (!(f >= 0.0 && f <= 1.0)) t.fail("fraction", "must lie in [0, 1]");
      return PartialWeld{f};
    });
    return true;
  }();
  (void)done;
}

std::vector<Measurement> run_disks(const std::string& law, const std::string& lines, double* v_right = nullptr) {
  Scene<2> sc = test::scene_from(test::two_disks_deck(law, "8 us", 40, lines));
  Runner<2> runner(sc, test::quiet());
  std::vector<Measurement> rows;
  runner.run([&](const Measurement& m) { rows.push_back(m); });
  if (v_right) {
    double m = 0, p = 0;
    for (std::size_t q = 0; q < sc.particles.size(); ++q)
      if (sc.field_names[static_cast<std::size_t>(sc.particles.field[q])] == "right") {
        m += sc.particles.mass[q];
        p += sc.particles.mass[q] * sc.particles.v[q].x();
      }
    *v_right = p / m;
  }
  return rows;
}

}  // namespace

TEST(ContactLawRegistry, AToyLawAtOneNodeGivesItsClosedForm) {
  register_toy();
  Grid<2> g;
  g.h = 1e-5;
  g.n = {1, 1};
  g.allocate(2);
  g.mass[0] = 2.0;
  g.mass[1] = 3.0;
  g.mom[0] = Vec<2>(2.0, 0.8);
  g.mom[1] = Vec<2>(-1.5, -0.6);
  g.vgrad[0] = Vec<2>(1.0, 0.0);
  g.vgrad[1] = Vec<2>(-0.5, 0.0);
  ContactMatrix cm;
  cm.fields = 2;
  cm.plugins.push_back(std::make_shared<detail::PluginOf<PartialWeld>>(PartialWeld{0.25}));
  cm.plugin_names.push_back("toy_partial_weld");
  PairLaw law;
  law.law = ContactLaw::registered;
  law.plugin = 0;
  cm.pair.assign(4, law);
  const Vec<2> pa = g.mom[0], pb = g.mom[1];
  const Vec<2> stick = (2.0 * pb - 3.0 * pa) / 5.0;
  field_contact<2>(g, cm, 2, 1e-9, 0.0);
  EXPECT_NEAR((g.mom[0] - (pa + 0.25 * stick)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((g.mom[1] - (pb - 0.25 * stick)).norm(), 0.0, 1e-15);
}

TEST(ContactLawRegistry, AToyLawRegisteredByOneCallIsBuiltFromADeckAndActsInARun) {
  register_toy();
  {
    Scene<2> sc = test::scene_from(test::two_disks_deck("toy_partial_weld", "8 us", 40, "fraction = 0.5\n"));
    EXPECT_EQ(sc.contact(0, 1).law, ContactLaw::registered);
    ASSERT_EQ(sc.contact(0, 1).plugin, 0);
    EXPECT_EQ(sc.contact.plugin_names.at(0), "toy_partial_weld");
  }
  // phi = 1 is the weld: the same history to round-off (an all-weld run takes the single-velocity
  // path, which sums each node's momentum in another order)
  const auto weld = run_disks("weld", "");
  const auto toy1 = run_disks("toy_partial_weld", "fraction = 1.0\n");
  ASSERT_EQ(weld.size(), toy1.size());
  for (std::size_t k = 0; k < weld.size(); ++k) {
    EXPECT_NEAR(weld[k].kinetic, toy1[k].kinetic, 1e-9 * weld[0].kinetic) << "row " << k;
    EXPECT_NEAR(weld[k].internal, toy1[k].internal, 1e-9 * weld[0].kinetic) << "row " << k;
  }
  // phi = 0: no exchange, the disks pass through each other at their own speed (free elastic
  // disks keep their momentum to round-off); any law, frictionless included, stops them instead
  double v0 = 0, vf = 0;
  run_disks("toy_partial_weld", "fraction = 0.0\n", &v0);
  run_disks("frictionless", "", &vf);
  EXPECT_NEAR(v0, -20.0, 1e-9);
  EXPECT_GT(vf, 0.0);  // rebounded
}

TEST(ContactLawRegistry, BadInputAndTakenNamesAreRefused) {
  register_toy();
  auto error_of = [](const std::string& lines, const std::string& law = "toy_partial_weld") {
    try {
      test::scene_from(test::two_disks_deck(law, "8 us", 40, lines));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error_of("fraction = 2\n").find("contact.fraction: must lie in [0, 1]"), std::string::npos)
      << error_of("fraction = 2\n");
  EXPECT_NE(error_of("fractio = 0.5\n").find("contact.fraction"), std::string::npos) << error_of("fractio = 0.5\n");
  EXPECT_NE(error_of("fraction = 0.5\n", "toy_partial_weldd").find("toy_partial_weld"), std::string::npos)
      << "the unknown-law message lists the registered laws";
  const auto noop = [](const ParamTable&) { return PartialWeld{}; };
  EXPECT_THROW(register_contact_law<PartialWeld>("coulomb", noop), std::invalid_argument);
  EXPECT_THROW(register_contact_law<PartialWeld>("toy_partial_weld", noop), std::invalid_argument);
  EXPECT_THROW(register_contact_law<PartialWeld>("Bad Name", noop), std::invalid_argument);
}
