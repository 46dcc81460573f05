// The material registry: every deviator x EOS pair of models.hpp's lists is a model, and a law of
// one's own is one class plus one register_material() call (docs/extending.md). The toy law here
// is a pure bulk response in rate form, s' = K tr(D) I, whose uniaxial-strain stress has the closed
// form sigma_xx = sigma_yy = sigma_zz = K ln(F_xx) (the driver's strain, logarithmic); a registry that built another
// law under its name, or passed it other conditions, would not give it.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "material_fixtures.hpp"
#include "materials/material.hpp"
#include "materials/point_driver.hpp"

using namespace pbx;

namespace {
template <int D>
class ToyBulk final : public Material<D> {
 public:
  ToyBulk(double rho, double K) : rho_(rho), K_(K) {}
  std::string model() const override { return "toy_bulk"; }
  double density() const override { return rho_; }
  double initial_wave_speed() const override { return std::sqrt(K_ / rho_); }
  MaterialStepResult update(const MaterialBatch<D>& b) const override {
    MaterialStepResult r;
    for (std::size_t k = 0; k < b.index.size(); ++k) {
      const auto p = b.index[k];
      const double tr = b.L[p].trace() * b.dt;  // tr(D) dt
      b.stress[p] += Sym3::identity(K_ * tr);
      r.max_wave_speed = std::max(r.max_wave_speed, std::sqrt(K_ * b.volume[p] / b.mass[p]));
    }
    return r;
  }

 private:
  double rho_, K_;
};

// The factory: its keys, refused when unknown, as every built-in model does.
template <int D>
std::unique_ptr<Material<D>> make_toy_bulk(const ParamTable& t, const MaterialContext&) {
  for (const auto& k : t.keys())
    if (k != "model" && k != "density" && k != "bulk_modulus") t.fail(k, "unknown key for model 'toy_bulk'");
  return std::make_unique<ToyBulk<D>>(t.positive("density", dim::density), t.positive("bulk_modulus", dim::pressure));
}
}  // namespace

TEST(Registry, EveryDeviatorAndEquationOfStatePairIsAModel) {
  const auto names = material_models();
  for (const char* dev : {"elastic", "j2", "viscoelastic"})
    for (const char* eos : {"linear", "mie_gruneisen", "tait"})
      EXPECT_NE(std::find(names.begin(), names.end(), std::string(dev) + "_" + eos), names.end()) << dev << "_" << eos;
  EXPECT_NE(std::find(names.begin(), names.end(), "linear_elastic"), names.end());
}

TEST(Registry, AToyLawRegisteredByOneCallIsBuiltFromADeckAndGivesItsClosedForm) {
  register_material<3>("toy_bulk", make_toy_bulk<3>);
  const auto names = material_models();
  EXPECT_NE(std::find(names.begin(), names.end(), "toy_bulk"), names.end());
  const auto m = test::material_from<3>("model = \"toy_bulk\"\ndensity = \"1000 kg/m3\"\nbulk_modulus = \"2 GPa\"\n");
  EXPECT_EQ(m->model(), "toy_bulk");
  PointLoad load;
  load.strain = -0.01;
  load.rate = 100.0;
  load.steps = 2000;
  const auto samples = drive_point(*m, load);
  const double K = 2e9, eps = samples.back().strain, expect = K * eps;  // eps = ln F_xx
  ASSERT_NEAR(eps, -0.01, 1e-12);
  EXPECT_NEAR(samples.back().stress.xx / expect, 1.0, 1e-6);
  EXPECT_NEAR(samples.back().stress.zz / expect, 1.0, 1e-6);
  // its own key check, a second registration and a bad name: clear errors
  EXPECT_THROW(test::material_from<3>("model = \"toy_bulk\"\ndensity = 1000.0\nbulk_modulus = 2e9\nshear = 1.0\n"),
               InputError);
  EXPECT_THROW(register_material<3>("toy_bulk", make_toy_bulk<3>), InputError);
  EXPECT_THROW(register_material<3>("j2_tait", make_toy_bulk<3>), InputError);  // a built-in name
  EXPECT_THROW(register_material<3>("Toy Bulk", make_toy_bulk<3>), InputError);
  // registered for 3-D only: a 2-D deck naming it is told the known models
  EXPECT_THROW(test::material_from<2>("model = \"toy_bulk\"\ndensity = 1000.0\nbulk_modulus = 2e9\n"), InputError);
}
