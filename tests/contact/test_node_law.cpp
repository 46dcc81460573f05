// The field contact law at single nodes against hand-computed impulses (docs/theory/contact.md):
// two bodies a (mass 2) and b (mass 3) meet at one node with outward normal of a along +x.
#include <cmath>

#include <gtest/gtest.h>

#include "contact/field_contact.hpp"
#include "contact/law_binder_layer.hpp"

using namespace pbx;

namespace {

Grid<2> one_node(int fields) {
  Grid<2> g;
  g.h = 1e-5;
  g.n = {1, 1};
  g.allocate(fields);
  return g;
}

PairLaw law_of(ContactLaw kind, double friction, double adhesion) {
  PairLaw p;
  p.law = kind;
  p.friction = friction;
  p.adhesion = adhesion;
  return p;
}

ContactMatrix matrix(int fields, PairLaw law, ContactNormal normal = ContactNormal::dominant) {
  ContactMatrix cm;
  cm.fields = fields;
  cm.normal = normal;
  cm.pair.assign(static_cast<std::size_t>(fields * fields), law);
  return cm;
}

// a on the left (grad V_a = sum V_p grad S points out of a: +x), b on the right.
void two_bodies(Grid<2>& g, const Vec<2>& va, const Vec<2>& vb) {
  g.mass[0] = 2.0;
  g.mass[1] = 3.0;
  g.mom[0] = 2.0 * va;
  g.mom[1] = 3.0 * vb;
  g.vgrad[0] = Vec<2>(1.0, -0.0);
  g.vgrad[1] = Vec<2>(-0.5, -0.0);
}

constexpr double kMuRed = 2.0 * 3.0 / 5.0;  // reduced mass

}  // namespace

TEST(NodeLaw, FrictionlessStopsNormalApproachKeepsTangential) {
  Grid<2> g = one_node(2);
  two_bodies(g, Vec<2>(1.0, 0.4), Vec<2>(-0.5, -0.2));
  const Vec<2> p0 = g.mom[0] + g.mom[1];
  const double w = field_contact<2>(g, matrix(2, law_of(ContactLaw::frictionless, 0, 0)), 2, 1e-9, 0.0);
  const Vec<2> va = g.mom[0] / 2.0, vb = g.mom[1] / 3.0;
  EXPECT_NEAR(va.x(), vb.x(), 1e-15);             // normal relative velocity removed
  EXPECT_NEAR(va.x(), (2.0 - 1.5) / 5.0, 1e-15);  // centre-of-mass normal velocity
  EXPECT_DOUBLE_EQ(va.y(), 0.4);                  // tangential untouched
  EXPECT_DOUBLE_EQ(vb.y(), -0.2);
  EXPECT_EQ((g.mom[0] + g.mom[1] - p0).norm(), 0.0);
  EXPECT_EQ(w, 0.0);
}

TEST(NodeLaw, SeparatingFieldsAreFree) {
  Grid<2> g = one_node(2);
  two_bodies(g, Vec<2>(-1.0, 0.4), Vec<2>(0.5, -0.2));
  const auto m0 = g.mom;
  field_contact<2>(g, matrix(2, law_of(ContactLaw::coulomb, 0.5, 0)), 2, 1e-9, 0.0);
  EXPECT_EQ(g.mom[0], m0[0]);
  EXPECT_EQ(g.mom[1], m0[1]);
}

TEST(NodeLaw, CoulombSticksBelowAndSlidesAboveTheCap) {
  // Normal relative speed 1.5, so the normal impulse is kMuRed * 1.5 = 1.8.
  for (const double vt : {0.2, 3.0}) {
    Grid<2> g = one_node(2);
    two_bodies(g, Vec<2>(1.0, vt), Vec<2>(-0.5, 0.0));
    const double mu = 0.3;
    const double w = field_contact<2>(g, matrix(2, law_of(ContactLaw::coulomb, mu, 0)), 2, 1e-9, 0.0);
    const Vec<2> va = g.mom[0] / 2.0, vb = g.mom[1] / 3.0;
    const double jt_stick = kMuRed * vt, jn = kMuRed * 1.5;
    const double jt = 2.0 * vt - g.mom[0].y();  // tangential impulse taken from a
    EXPECT_NEAR(va.x(), vb.x(), 1e-15);
    if (jt_stick <= mu * jn) {
      EXPECT_NEAR(va.y(), vb.y(), 1e-15);  // stick
      EXPECT_NEAR(jt, jt_stick, 1e-14);
      EXPECT_EQ(w, 0.0);
    } else {
      EXPECT_NEAR(jt, mu * jn, 1e-14);  // transmitted shear = mu x normal
      const double slip = std::abs(va.y() - vb.y());
      EXPECT_GT(slip, 0.0);
      // friction impulse x mean of the slip speeds before (vt) and after: the kinetic energy lost
      EXPECT_NEAR(w, mu * jn * 0.5 * (vt + slip), 1e-14);
      const double ke0 = 0.5 * 2.0 * vt * vt, ke1 = 0.5 * 2.0 * va.y() * va.y() + 0.5 * 3.0 * vb.y() * vb.y();
      EXPECT_NEAR(w, ke0 - ke1, 1e-14);
    }
    EXPECT_NEAR((g.mom[0] + g.mom[1]).y(), 2.0 * vt, 1e-14);
  }
}

TEST(NodeLaw, AdhesionAddsSaAcDtToTheCap) {
  Grid<2> g = one_node(2);
  two_bodies(g, Vec<2>(1.0, 3.0), Vec<2>(-0.5, 0.0));
  const double mu = 0.1, sa = 1e8, dt = 1e-4;  // S_a A_c dt = 0.1, mu jn = 0.18
  field_contact<2>(g, matrix(2, law_of(ContactLaw::adhesion, mu, sa)), 2, dt, 0.0);
  const double jt = 6.0 - g.mom[0].y();
  EXPECT_NEAR(jt, sa * g.h * dt + mu * kMuRed * 1.5, 1e-14);
}

TEST(NodeLaw, WeldGivesCentreOfMassVelocity) {
  Grid<2> g = one_node(2);
  two_bodies(g, Vec<2>(-1.0, 0.4), Vec<2>(0.5, -0.2));  // even separating
  field_contact<2>(g, matrix(2, law_of(ContactLaw::weld, 0, 0)), 2, 1e-9, 0.0);
  const Vec<2> vcm = (Vec<2>(-2.0, 0.8) + Vec<2>(1.5, -0.6)) / 5.0;
  EXPECT_NEAR((g.mom[0] / 2.0 - vcm).norm(), 0.0, 1e-15);
  EXPECT_NEAR((g.mom[1] / 3.0 - vcm).norm(), 0.0, 1e-15);
}

TEST(NodeLaw, NormalOptionsDecideTheDirection) {
  // Oblique gradients: dominant takes a's (larger) gradient, own gives each field its own.
  Grid<2> g = one_node(2);
  two_bodies(g, Vec<2>(1.0, 1.0), Vec<2>(0.0, 0.0));
  g.vgrad[0] = Vec<2>(2.0, -0.0);
  g.vgrad[1] = Vec<2>(-0.0, -1.0);
  const PairLaw fl = law_of(ContactLaw::frictionless, 0, 0);
  Grid<2> dom = g;
  field_contact<2>(dom, matrix(2, fl, ContactNormal::dominant), 2, 1e-9, 0.0);
  // n = +x: only the x relative velocity is removed.
  EXPECT_NEAR(dom.mom[0].x() / 2.0, dom.mom[1].x() / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(dom.mom[0].y(), 2.0);
  Grid<2> avg = g;
  field_contact<2>(avg, matrix(2, fl, ContactNormal::average), 2, 1e-9, 0.0);
  const Vec<2> n = Vec<2>(2.0, 1.0).normalized();
  EXPECT_NEAR((avg.mom[0] / 2.0 - avg.mom[1] / 3.0).dot(n), 0.0, 1e-15);
  EXPECT_NEAR((avg.mom[0] + avg.mom[1] - g.mom[0] - g.mom[1]).norm(), 0.0, 1e-15);
  // own: each field against the other along its own gradient, a along +x, b along -y; both
  // approach, d_a = (-1.2, 0), d_b = (0, 1.2), and the residual R = (-1.2, 1.2) is shared by mass:
  // a ends at (2, 2) + d_a - (2/5) R = (1.28, 1.52), b at (0.72, 0.48).
  Grid<2> own = g;
  field_contact<2>(own, matrix(2, fl, ContactNormal::own), 2, 1e-9, 0.0);
  EXPECT_NEAR(own.mom[0].x(), 1.28, 1e-14);
  EXPECT_NEAR(own.mom[0].y(), 1.52, 1e-14);
  EXPECT_NEAR(own.mom[1].x(), 0.72, 1e-14);
  EXPECT_NEAR(own.mom[1].y(), 0.48, 1e-14);
}

TEST(NodeLaw, ThreeFieldsConserveMomentumAndStopApproach) {
  Grid<2> g = one_node(3);
  g.mass[0] = 1.0;
  g.mass[1] = 2.0;
  g.mass[2] = 0.5;
  g.mom[0] = Vec<2>(1.0, 0.3);
  g.mom[1] = Vec<2>(-2.0, 0.1);
  g.mom[2] = Vec<2>(0.2, -0.4);
  g.vgrad[0] = Vec<2>(1.0, -0.1);
  g.vgrad[1] = Vec<2>(-0.8, -0.0);
  g.vgrad[2] = Vec<2>(-0.1, 0.3);
  const Vec<2> p0 = g.mom[0] + g.mom[1] + g.mom[2];
  field_contact<2>(g, matrix(3, law_of(ContactLaw::coulomb, 0.3, 0)), 3, 1e-9, 0.0);
  EXPECT_NEAR((g.mom[0] + g.mom[1] + g.mom[2] - p0).norm(), 0.0, 1e-15);
  // Field 0 no longer approaches the rest along its normal (up to the momentum correction).
  const Vec<2> n0 = Vec<2>(1.0, -0.1).normalized();
  const Vec<2> vr = (g.mom[1] + g.mom[2]) / 2.5;
  EXPECT_LT((g.mom[0] / 1.0 - vr).dot(n0), 0.05);
}

namespace {
// Two bonded fields at one node joined by a binder layer (thickness t_a on a's particles, t_b on
// b's), b displaced from its reference by (-closing, sliding): a compressed and sheared layer.
struct LayerNode {
  Grid<2> g = one_node(2);
  LayerSums<2> s;
  ContactMatrix cm;
  LayerNode(double t_a, double t_b, double closing, double sliding, double mu, bool cap) {
    two_bodies(g, Vec<2>::Zero(), Vec<2>::Zero());
    s.allocate(g.mass.size());
    const double m[2] = {2.0, 3.0};
    const Vec<2> shift[2] = {Vec<2>::Zero(), Vec<2>(-closing, sliding)};
    const double t[2] = {t_a, t_b};
    for (int f = 0; f < 2; ++f) {
      const Vec<2> X(f == 0 ? 1e-5 : 2e-5, 1e-5);  // mass centres, reference
      g.moff[f] = m[f] * (X + shift[f]);
      s.mref[f] = m[f] * X;
      s.mdef[f] = m[f] * Mat<2>::Identity();
      s.mbond[f] = m[f];
      s.minvt[f] = m[f] / t[f];
      s.mnorm[f] = m[f] * Vec<2>(f == 0 ? 1.0 : -1.0, 0.0);  // each side's normal towards the other
    }
    cm = matrix(2, law_of(ContactLaw::binder_layer, mu, 0));
    for (auto& p : cm.pair) p.layer = 0;
    LayerLaw L;
    L.binder = "f2314";
    L.friction = mu;
    L.shear_cap = cap;
    L.time = {0.0};
    L.normal = {3.6e8};  // M_b, Pa
    L.shear = {7.0e7};   // G_b, Pa
    L.at_time(0.0);
    cm.layers.push_back(L);
  }
};
}  // namespace

// The spring's impulse by hand: area 1/2 |(g_a - g_b).n| = 0.75 (m per m of depth), stiffness
// area x modulus x mean 1/t of the node's bonded mass, backward Euler factor 1/(1 + k dt^2/m_red).
// Uncapped the shear is the spring's; with Eq. 7 it is capped at mu x the normal impulse; with the
// per-side thicknesses the node uses the mass-weighted mean of 1/t (2 kg at 4 um, 3 kg at 8 um).
TEST(NodeLaw, BinderLayerSpringWithPairThicknessAndCoulombCap) {
  const double dt = 1e-9, closing = 0.2e-6, sliding = 1.0e-6, mu = 0.3;
  for (const bool cap : {false, true}) {
    for (const double tb : {4e-6, 8e-6}) {
      LayerNode n(4e-6, tb, closing, sliding, mu, cap);
      const double inv_t = (2.0 / 4e-6 + 3.0 / tb) / 5.0;
      field_contact<2>(n.g, n.cm, 2, dt, 0.0, nullptr, true, nullptr, &n.s);
      const double kn = 0.75 * 3.6e8 * inv_t, kt = 0.75 * 7.0e7 * inv_t;
      const double Jn = dt * kn / (1.0 + kn * dt * dt / kMuRed) * closing;  // pushes a to -x
      double Jt = dt * kt / (1.0 + kt * dt * dt / kMuRed) * sliding;        // drags a to +y
      ASSERT_LT(mu * Jn, 0.5 * Jt) << "the cap must bind in this case";
      if (cap) Jt = mu * Jn;
      EXPECT_NEAR(n.g.mom[0].x(), -Jn, 1e-12 * Jn) << cap << " " << tb;
      EXPECT_NEAR(n.g.mom[0].y(), Jt, 1e-12 * Jn) << cap << " " << tb;
      EXPECT_NEAR((n.g.mom[0] + n.g.mom[1]).norm(), 0.0, 1e-15 * Jn);
    }
  }
}

// In tension the layer carries no shear under Eq. 7 (S_a = 0), and still its normal spring.
TEST(NodeLaw, BinderLayerCappedShearVanishesInTension) {
  const double dt = 1e-6;
  LayerNode n(4e-6, 4e-6, -0.2e-6, 0.3e-6, 0.3, true);
  field_contact<2>(n.g, n.cm, 2, dt, 0.0, nullptr, true, nullptr, &n.s);
  EXPECT_GT(n.g.mom[0].x(), 0.0);  // a pulled towards b
  EXPECT_EQ(n.g.mom[0].y(), 0.0);
}

// film = "bonds": a pair's spring by hand. coef 0.5 m, k_n = 0.5 x 3.6e8, k_t = 0.5 x 7e7 (N/m per m
// of depth); closing by 0.2 um along n0 = +x and sliding by 1 um along +y: the normal force on p is
// k_n s_n n0 (pushed away from q, -x), the shear k_t s_t uncapped and mu x |f_n| with Eq. 7; none in
// tension; the energy F^2 / 2k per spring.
TEST(NodeLaw, BondPairForceIsTheSpringWithTheCoulombCap) {
  LayerLaw L;
  L.friction = 0.3;
  L.kn = 3.6e8;
  L.kt = 7.0e7;
  const double coef = 0.5, kn = coef * L.kn, kt = coef * L.kt;
  const Vec<2> n0(1.0, 0.0), closing(-0.2e-6, 1.0e-6), opening(0.2e-6, 1.0e-6);
  for (const bool cap : {false, true}) {
    L.shear_cap = cap;
    const BondForce<2> c = bond_force<2>(L, coef, n0, closing);
    const double fn = kn * -0.2e-6, ft_spring = kt * 1.0e-6;
    ASSERT_LT(0.3 * std::abs(fn), 0.5 * ft_spring) << "the cap must bind in this case";
    const double ft = cap ? 0.3 * std::abs(fn) : ft_spring;
    EXPECT_NEAR(c.f.x(), fn, 1e-12 * std::abs(fn)) << cap;
    EXPECT_NEAR(c.f.y(), ft, 1e-12 * ft) << cap;
    EXPECT_NEAR(c.energy, 0.5 * (fn * fn / kn + ft * ft / kt), 1e-12 * c.energy) << cap;
    const BondForce<2> o = bond_force<2>(L, coef, n0, opening);
    EXPECT_NEAR(o.f.x(), kn * 0.2e-6, 1e-12 * kn * 0.2e-6) << cap;  // pulled towards q
    EXPECT_EQ(o.f.y(), cap ? 0.0 : ft_spring) << cap;
  }
  L.shear_cap = true;  // a small slide below the cap keeps the spring's shear
  const BondForce<2> small = bond_force<2>(L, coef, n0, Vec<2>(-0.2e-6, 0.1e-6));
  EXPECT_NEAR(small.f.y(), kt * 0.1e-6, 1e-12 * kt * 0.1e-6);
}

// Squeezed out: a closure beyond closure x t (here the whole 4 um layer) hands the node to
// Coulomb contact; at rest that exchanges nothing.
TEST(NodeLaw, BinderLayerSqueezedOutPastItsThickness) {
  LayerNode n(4e-6, 4e-6, 4.1e-6, 0.0, 0.3, true);
  field_contact<2>(n.g, n.cm, 2, 1e-6, 0.0, nullptr, true, nullptr, &n.s);
  EXPECT_EQ(n.g.mom[0].x(), 0.0);
  LayerNode m(4e-6, 4e-6, 3.9e-6, 0.0, 0.3, true);
  field_contact<2>(m.g, m.cm, 2, 1e-6, 0.0, nullptr, true, nullptr, &m.s);
  EXPECT_LT(m.g.mom[0].x(), 0.0);
}

// Torn open past its own thickness (a normal strain of 100 %) the layer no longer pulls: the pair
// is Coulomb, inactive while the sides are apart; just below, the spring pulls a towards b.
TEST(NodeLaw, BinderLayerTornOpenPastItsThickness) {
  LayerNode n(4e-6, 4e-6, -4.1e-6, 0.0, 0.3, true);
  field_contact<2>(n.g, n.cm, 2, 1e-9, 0.0, nullptr, true, nullptr, &n.s);
  EXPECT_EQ(n.g.mom[0].x(), 0.0);
  LayerNode m(4e-6, 4e-6, -3.9e-6, 0.0, 0.3, true);
  field_contact<2>(m.g, m.cm, 2, 1e-9, 0.0, nullptr, true, nullptr, &m.s);
  EXPECT_GT(m.g.mom[0].x(), 0.0);
}

// Film flow (flow_stress / flow_factor, issue 23's calibration): the compressive normal impulse is
// capped at dt x area x the flow pressure, the shear cap follows the capped normal (mu x it), the
// closure beyond the cap is booked as dissipated work (cap force x closing, half per side, both
// sides here: the whole), and a flowing layer is not squeezed out past its thickness. The cap of
// flow_factor is that factor times the binder's current secant G_b (7e7 Pa here).
TEST(NodeLaw, FlowingBinderLayerCapsItsNormalTraction) {
  const double dt = 1e-9, closing = 0.2e-6, sliding = 1.0e-6, mu = 0.3, area = 0.75;
  const double inv_t = 1.0 / 4e-6;
  const double kn = area * 3.6e8 * inv_t;
  const double Jspring = dt * kn / (1.0 + kn * dt * dt / kMuRed) * closing;
  for (const int how : {0, 1}) {
    LayerNode n(4e-6, 4e-6, closing, sliding, mu, true);
    const double p = 0.25 * Jspring / (dt * area);  // a quarter of the spring's traction: the cap binds
    if (how == 0)
      n.cm.layers[0].flow_stress = p;
    else
      n.cm.layers[0].flow_factor = p / 7.0e7;
    const double w = field_contact<2>(n.g, n.cm, 2, dt, 0.0, nullptr, true, nullptr, &n.s);
    const double J = dt * area * p;
    EXPECT_NEAR(n.g.mom[0].x(), -J, 1e-9 * J) << how;
    EXPECT_NEAR(n.g.mom[0].y(), mu * J, 1e-9 * J) << how;  // Eq. 7 on the capped traction
    EXPECT_NEAR((n.g.mom[0] + n.g.mom[1]).norm(), 0.0, 1e-15 * J);
    // from rest the step adds no closure (the cap's impulse only slows the fields apart): no flow work
    EXPECT_EQ(w, 0.0);
  }
  // Past its thickness a flowing layer still pushes at its cap (the plain layer hands over to Coulomb),
  // and holds the elastic energy of the cap, F^2 / 2k with F = cap x area (half per side, both sides
  // here), not 1/2 k jump^2 of its whole closure (which grows without bound as grains pass through).
  LayerNode deep(4e-6, 4e-6, 6e-6, 0.0, mu, true);
  deep.cm.layers[0].flow_stress = 1e6;
  double stored = 0;
  field_contact<2>(deep.g, deep.cm, 2, dt, 0.0, nullptr, true, &stored, &deep.s);
  EXPECT_NEAR(deep.g.mom[0].x(), -dt * area * 1e6, 1e-9 * dt * area * 1e6);
  const double F = area * 1e6, k = area * 3.6e8 / 4e-6;
  EXPECT_NEAR(stored, 0.5 * F * F / k, 1e-9 * F * F / k);
}

// The flow work: fields closing at a speed v for one step against a capped layer dissipate the cap
// force times the closure the step adds (the spring's elastic part does not change at the cap).
TEST(NodeLaw, FlowingBinderLayerBooksItsPlasticWork) {
  const double dt = 1e-9, closing = 0.2e-6, p = 1e6, area = 0.75;
  LayerNode n(4e-6, 4e-6, closing, 0.0, 0.3, true);
  n.cm.layers[0].flow_stress = p;
  const Vec<2> va(5.0, 0.0), vb(-5.0, 0.0);  // closing at 10 m/s
  n.g.mom[0] = 2.0 * va;
  n.g.mom[1] = 3.0 * vb;
  const double w = field_contact<2>(n.g, n.cm, 2, dt, 0.0, nullptr, true, nullptr, &n.s);
  const double J = dt * area * p;
  // end-of-step closure added: dt x (relative speed after the cap's impulse)
  const double vrel_after = 10.0 - J / kMuRed;
  EXPECT_NEAR(w, (J / dt) * dt * vrel_after, 1e-9 * w);
}

// The jump is read in the current configuration. Both sides deformed alike by F = R S (compressed
// to 95 % along their contact normal, then rotated by 30 degrees), b displaced from a by `closing`
// along the current normal n = R e_x: the spring pushes with dt k closing along n and no shear
// (backward Euler factor as above). Reading the jump in the reference configuration (F^-1 of it)
// gave the normal impulse x cos 30 / 0.95 (-9 %) and a tangential one of 0.45 x it.
TEST(NodeLaw, BinderLayerReadsTheJumpOfARotatedCompressedPairInTheCurrentConfiguration) {
  const double dt = 1e-9, closing = 0.2e-6, t = 4e-6, th = std::acos(-1.0) / 6.0;
  Mat<2> R;
  R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  Mat<2> S = Mat<2>::Identity();
  S(0, 0) = 0.95;
  const Mat<2> F = R * S;
  const Vec<2> n = R * Vec<2>(1.0, 0.0);
  LayerNode node(t, t, 0.0, 0.0, 0.3, false);
  const double m[2] = {2.0, 3.0};
  const Vec<2> X[2] = {Vec<2>(1e-5, 1e-5), Vec<2>(2e-5, 1e-5)}, c(3e-6, -2e-6);
  for (int f = 0; f < 2; ++f) {
    const Vec<2> x = F * X[f] + c - (f == 1 ? closing : 0.0) * n;
    node.g.moff[f] = m[f] * x;
    node.s.mref[f] = m[f] * X[f];
    node.s.mdef[f] = m[f] * F;
    node.s.mnorm[f] = m[f] * (f == 0 ? 1.0 : -1.0) * Vec<2>(F.inverse().transpose() * Vec<2>(1.0, 0.0));
    node.g.vgrad[f] = (f == 0 ? 1.0 : -0.5) * n;  // interface area 0.75 as above
  }
  field_contact<2>(node.g, node.cm, 2, dt, 0.0, nullptr, true, nullptr, &node.s);
  const double kn = 0.75 * 3.6e8 / t;
  const double Jn = dt * kn / (1.0 + kn * dt * dt / kMuRed) * closing;
  EXPECT_NEAR(node.g.mom[0].dot(n), -Jn, 1e-9 * Jn);
  EXPECT_NEAR(node.g.mom[0].dot(Vec<2>(-n.y(), n.x())), 0.0, 1e-9 * Jn);
}
