// The binder_layer contact law (contact/binder_layer.hpp) against closed forms.
//
// Layered column in the die (uniaxial strain): two slabs of one linear-elastic material on two
// fields, joined by a spring interface of normal stiffness D_n (Pa/m), compressed by the punch.
// The slabs are hypoelastic, sigma = M ln(h0/h), so at punch stress sigma the punch has moved
//   u(sigma) = H (1 - exp(-sigma/M)) + sigma/D_n
// and the compliance between two stress levels is [u(s2) - u(s1)]/(s2 - s1), for D_n H/M = 0.3, 1
// and 10 (the interface takes 77 %, 50 % and 9 % of the compliance; at 3 % strain its closure is
// then 0.3-1.1 cells), with the interface on a node line and half-way between two, D_t = 0.3 D_n,
// mass scaling 10. Two checks:
// - the spring alone: its closure read on the particles at the end (the gap between the two
//   slabs' facing rows) against sigma / D_n with sigma the slabs' own stress, within 0.3 % (6 %
//   for the 1.3 um closure of ratio 10, see below). Measured 2026-12-06 with the springs' impulses
//   handed through the particles (the default since then): -0.03, +0.00, +1.11 % (node line), +0.08,
//   -0.27, -4.40 % (half-way); at the node alone +0.04, +0.02, -1.00 / +0.09, -0.27, -0.90 %. With the
//   jump read in the reference configuration (before 2026-12-06) it was -0.44, -0.98, -3.5 %: 1/F
//   too stiff.
// - the punch stroke's compliance against the closed form within 2 %: measured -0.55, -1.00,
//   -0.91 % (node line), -0.78, -0.82, -0.46 % (half-way); at the node alone -0.49, -0.80, +0.13 /
//   -0.67, -0.59, +0.09 %. This one also carries the column's own
//   error, not the spring's: the bonded column reads +1.1 % at these cells, -1.3 % at 20 um and
//   +0.2 % at 5 um (least squares over 1-3 %; the punch acts on the first node row behind its
//   face, a sawtooth of a few hundredths of a cell), and the particle rows next to the interface
//   strain about half as much as the slab (a few rows of a 96-row column).
// The stiff limit (D_n H/M = 1e6) gives the bonded column within 1 % (mass scaling 100, +0.6 %).
// With normals and area from the volume gradients alone, the die-wall edges of the interface
// tilted the normal by up to 55 degrees and added 41 % to the area: -7 % (D_t = D_n) and +9 %
// (D_t = 0.3 D_n) at D_n H/M = 1 (docs/theory/contact.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "../engine/block_deck.hpp"
#include "../engine/scene_fixture.hpp"
#include "core/error.hpp"
#include "solver/scene.hpp"

using namespace pbx;

namespace {
constexpr double K = 10.59e9, G = 11.5e9, M = K + 4 * G / 3, H = 0.48e-3;

// Two slabs of material "block" on fields "lower" and "upper", width w_mm, meeting at y0_um (from
// the bottom y = 0 to the top y1_mm), joined by the law with stiffnesses dn, dt (Pa/m).
std::string two_slabs(double w_mm, double y0_um, double y1_mm, double dn, double dt) {
  return fmt::format(R"([[geometry]]
min = ["0 mm", "0 mm"]
max = ["{0} mm", "{1} um"]
material = "block"
field = "lower"
[[geometry]]
min = ["0 mm", "{1} um"]
max = ["{0} mm", "{2} mm"]
material = "block"
field = "upper"
[contact]
default = "frictionless"
[[contact.pair]]
materials = ["block", "block"]
law = "binder_layer"
friction = 0.0
normal_stiffness = {3}
shear_stiffness = {4}
)",
                     w_mm, y0_um, y1_mm, dn, dt);
}

// The die column of the engine tests (tests/engine/block_deck.hpp) cut into two slabs on two
// fields at height lower_height_um, joined by the law.
std::string column_deck(double lower_height_um, double dn, double dt, double mass_scaling = 100) {
  const std::string block = test::block_deck(mass_scaling, 0.03);
  return block.substr(0, block.find("[[geometry]]")) + two_slabs(0.04, lower_height_um, 0.48, dn, dt);
}

struct Row {
  double strain, stress;
};

// The interface's closure read on the particles at the end of a run: the gap between the lower
// slab's top particle row and the upper slab's bottom row less their half-spacings (each the
// spacing of its slab's last two rows), and the column's stress, the mean -sigma_yy of the
// particles of each slab's middle.
struct Closure {
  double jump = 0, stress = 0;
};

template <int D>
Closure closure_on_particles(const Scene<D>& sc) {
  const auto& P = sc.particles;
  std::vector<double> rows_of[2];
  std::vector<std::pair<double, double>> all;  // (y, -sigma_yy)
  for (std::size_t p = 0; p < P.size(); ++p) {
    rows_of[P.field[p]].push_back(P.x[p][1]);
    all.push_back({P.x[p][1], -P.stress[p].yy});
  }
  auto rows = [](std::vector<double> y) {  // row heights: particles closer than 1 um share a row
    std::sort(y.begin(), y.end());
    std::vector<double> mean;
    std::vector<int> count;
    for (std::size_t i = 0; i < y.size(); ++i) {
      if (i == 0 || y[i] - y[i - 1] > 1e-6) mean.push_back(0.0), count.push_back(0);
      mean.back() += y[i], ++count.back();
    }
    for (std::size_t k = 0; k < mean.size(); ++k) mean[k] /= count[k];
    return mean;
  };
  const auto lo = rows(rows_of[0]), up = rows(rows_of[1]);
  const double dl = lo.end()[-1] - lo.end()[-2], du = up[1] - up[0];
  Closure c;
  c.jump = (up[0] - lo.back()) - 0.5 * (dl + du);
  // the middle 60 % of each slab: the interface disturbs its particles' stress over 2-3 cells
  // (the overlapping rows read half the column's stress), the floor and the punch over 1-3
  double sum = 0;
  int n = 0;
  for (const auto& [y, s] : all) {
    const bool lower = y < lo.back() && y > lo.front() + 0.2 * (lo.back() - lo.front()) &&
                       y < lo.front() + 0.8 * (lo.back() - lo.front());
    const bool upper =
        y > up.front() + 0.2 * (up.back() - up.front()) && y < up.front() + 0.8 * (up.back() - up.front());
    if (lower || upper) sum += s, ++n;
  }
  c.stress = sum / n;
  return c;
}

std::vector<Row> run_column(double lower_height_um, double dn, Closure* closure = nullptr, double mass_scaling = 100) {
  Scene<2> sc = test::scene_from(column_deck(lower_height_um, dn, 0.3 * dn, mass_scaling));
  Runner<2> r(sc, test::quiet());
  std::vector<Row> rows;
  r.run([&](const Measurement& m) { rows.push_back({m.strain, m.punch_stress}); });
  if (closure) *closure = closure_on_particles(sc);
  return rows;
}

// Measured compliance du/dsigma between the first row past strain a and the last row before b,
// and the closed form over the same stresses.
void compliance(const std::vector<Row>& rows, double a, double b, double dn, double& measured, double& closed) {
  const Row* r1 = nullptr;
  const Row* r2 = nullptr;
  for (const auto& r : rows) {
    if (!r1 && r.strain >= a) r1 = &r;
    if (r.strain <= b) r2 = &r;
  }
  ASSERT_TRUE(r1 && r2 && r2 != r1);
  const auto u = [&](double s) { return H * (1.0 - std::exp(-s / M)) + s / dn; };
  measured = H * (r2->strain - r1->strain) / (r2->stress - r1->stress);
  closed = (u(r2->stress) - u(r1->stress)) / (r2->stress - r1->stress);
}
}  // namespace

TEST(BinderLayer, LayeredColumnInUniaxialStrainMatchesTheSeriesCompliance) {
  for (const double lower : {240.0, 245.0}) {  // interface on a node line; half-way between two
    for (const double ratio : {0.3, 1.0, 10.0}) {
      const double dn = ratio * M / H;
      Closure c;
      const auto rows = run_column(lower, dn, &c, 10);
      double measured = 0, closed = 0;
      compliance(rows, 0.01, 0.03, dn, measured, closed);
      std::fprintf(stderr,
                   "interface at %.0f um, D_n H/M = %g: compliance %+.2f %% of the closed form; closure on the "
                   "particles %.4f um, %+.2f %% of sigma/D_n\n",
                   lower, ratio, 100.0 * (measured / closed - 1.0), -1e6 * c.jump,
                   100.0 * (-c.jump * dn / c.stress - 1.0));  // the figures docs/theory/contact.md quotes
      EXPECT_NEAR(measured / closed, 1.0, 0.02) << "interface at " << lower << " um, D_n H/M = " << ratio;
      // the spring itself, without the punch and the slabs: closure = sigma / D_n within 0.3 % for
      // closures of 7-11 um (ratios 0.3 and 1), 6 % for the 1.3 um one (ratio 10). The spring's
      // impulse reaches the slabs through the particles that define its jump (since 2026-12-06), so
      // the traction enters over the band of rows within a cell of the interface and the facing rows'
      // gap holds part of that band's strain: about 0.06 um, -4.4 % of the 1.3 um closure with the
      // interface half-way between node lines (+1.1 % on a node line; at the node alone it was -1.0 /
      // -0.9 %, the row estimate's own 0.02 um), 0.1 % of the larger closures.
      EXPECT_NEAR(-c.jump * dn / c.stress, 1.0, ratio < 5.0 ? 0.003 : 0.06) << "interface at " << lower << " um";
    }
  }
}

// The bonded zone must reach as deep as the closure: at 5 um cells the column's layer (D_n H/M =
// 0.3) closes by 11 um, 2.2 cells, and the nodes the two slabs share then hold particles that deep.
// With bond_depth = 16 um (the closure plus a cell) the spring holds as at 10 um cells (closure
// on the particles within 0.3 % of sigma/D_n, stroke within 2 %); with the default two cells of a
// law given by its stiffnesses (it has no thickness to size the zone from) the shared nodes' mass
// is mostly unbonded, the pair turns to Coulomb contact and the stroke's compliance reads -45 %
// (measured 2026-12-06; asserted below 30 % off, so a zone sized too shallow is seen).
TEST(BinderLayer, BondedZoneDeeperThanTheClosureKeepsTheSpringAtFineCells) {
  const double ratio = 0.3, dn = ratio * M / H;
  for (const bool deep : {true, false}) {
    std::string d = column_deck(240.0, dn, 0.3 * dn, 10);
    const std::string cell = "cell_size = \"10 um\"";
    d.replace(d.find(cell), cell.size(), "cell_size = \"5 um\"");
    if (deep) d.insert(d.find("normal_stiffness"), "bond_depth = \"16 um\"\n");
    Scene<2> sc = test::scene_from(d);
    Runner<2> r(sc, test::quiet());
    std::vector<Row> rows;
    r.run([&](const Measurement& m) { rows.push_back({m.strain, m.punch_stress}); });
    double measured = 0, closed = 0;
    compliance(rows, 0.01, 0.03, dn, measured, closed);
    const Closure c = closure_on_particles(sc);
    std::fprintf(stderr, "5 um cells, bond_depth %s: compliance %+.2f %%, closure %.3f um (%+.2f %% of sigma/D_n)\n",
                 deep ? "16 um" : "default (10 um)", 100 * (measured / closed - 1), -1e6 * c.jump,
                 100.0 * (-c.jump * dn / c.stress - 1.0));
    if (deep) {
      EXPECT_NEAR(measured / closed, 1.0, 0.02);
      EXPECT_NEAR(-c.jump * dn / c.stress, 1.0, 0.003);
    } else {
      EXPECT_LT(measured / closed, 0.7);
    }
  }
}

TEST(BinderLayer, StiffLayerGivesTheBondedColumn) {
  const double dn = 1e6 * M / H;
  const auto rows = run_column(240.0, dn);
  double measured = 0, closed = 0;
  compliance(rows, 0.01, 0.03, dn, measured, closed);
  std::fprintf(stderr, "bonded limit: compliance %+.2f %% of the closed form\n", 100.0 * (measured / closed - 1.0));
  EXPECT_NEAR(measured / closed, 1.0, 0.01);
}

// The energy the springs hold (history column layer_energy_J_per_m) is the interface's strain
// energy: with the punch stress sigma carried through an interface of width w, w sigma^2 / (2 D_n)
// per metre of depth (no shear in uniaxial strain). From 1 % strain: the mean ratio within 2 %, each
// row within 5 % (a row's punch stress is its mean over the row, the energy the state at its end;
// measured 2026-12-05: mean +0.8 %, rows -0.2 to +2.4 %). Counting each side's spring whole, or
// a quarter, would read 2.0 or 0.5.
TEST(BinderLayer, SpringEnergyIsTheInterfacesStrainEnergy) {
  const double dn = M / H, w = 0.04e-3;
  Scene<2> sc = test::scene_from(column_deck(240.0, dn, 0.3 * dn));
  Runner<2> r(sc, test::quiet());
  double worst = 0, sum = 0;
  int rows = 0;
  r.run([&](const Measurement& m) {
    ASSERT_EQ(m.layer_energy.size(), 1u);
    EXPECT_LE(m.layer_energy[0], m.internal);
    if (m.strain < 0.01) return;
    const double ratio = m.layer_energy[0] / (w * m.punch_stress * m.punch_stress / (2.0 * dn));
    worst = std::max(worst, std::abs(ratio - 1.0));
    sum += ratio;
    ++rows;
  });
  ASSERT_GT(rows, 10);
  std::fprintf(stderr, "spring energy / (w sigma^2 / 2 D_n): mean %.4f, worst row %+.2f %% over %d rows\n", sum / rows,
               100.0 * worst, rows);
  EXPECT_NEAR(sum / rows, 1.0, 0.02);
  EXPECT_LT(worst, 0.05);
}

namespace {
// The column deck with the layer's stiffnesses taken from the paper's F2314 calibration
// (examples/paper/base.toml) at temperature T.
std::string binder_deck(double T, const char* load_time) {
  std::string d = column_deck(240.0, 1.0, 1.0);
  const std::size_t at = d.find("normal_stiffness");
  d = d.substr(0, at) + fmt::format("binder = \"f2314\"\nthickness = \"2 um\"\nload_time = {}\n", load_time);
  d += fmt::format(R"(
[materials.f2314]
model = "viscoelastic_tait"
density = "2.02 g/cm3"
reference_temperature = "293 K"
thermal_expansion = "4.5e-4 1/K"
long_term_shear_modulus = "10 MPa"
prony_shear_moduli = ["12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa"]
prony_shear_times = ["1e-7 s", "1e-6 s", "1e-5 s", "1e-4 s", "1e-3 s", "1e-2 s", "1e-1 s", "1 s"]
shift = "arrhenius"
activation_energy = "100 kJ/mol"
tait_c = 0.08936
tait_k0 = "0.27 GPa"
tait_b1 = "4e-3 1/K"
)");
  d.replace(d.find("end_strain = 0.03"), 17, "end_strain = 0.06");  // the elapsed table then reaches 100 us
  const std::size_t run = d.find("[run]\n");
  return d.insert(run + 6, fmt::format("temperature = \"{} K\"\n", T));
}
}  // namespace

// The law's moduli D_n t and D_t t are the binder's secant constrained and shear moduli over the load time: at
// 100 us the F2314 calibration's point-driver values of docs/theory/materials.md (shear 68.6 and
// 21.2 MPa, K0 270 and 196 MPa at 293 and 373 K; M = K0 + 4/3 G), within 1 %; with
// load_time = "elapsed" the stiffness at t = 100 us is the same secant.
TEST(BinderLayer, StiffnessesAreTheBindersSecantModuliOverTheLoadTime) {
  struct Case {
    double T, G, K0;
  };
  for (const Case c : {Case{293, 68.6e6, 270e6}, Case{373, 21.2e6, 196e6}}) {
    Scene<2> fixed = test::scene_from(binder_deck(c.T, "\"100 us\""));
    ASSERT_EQ(fixed.contact.layers.size(), 1u);
    const LayerLaw& l = fixed.contact.layers[0];
    EXPECT_NEAR(l.kt, c.G, 0.01 * c.G) << c.T;
    EXPECT_NEAR(l.kn, c.K0 + 4.0 / 3.0 * c.G, 0.01 * (c.K0 + 4.0 / 3.0 * c.G)) << c.T;
    // the bonded particles carry 1/t of the 2 um layer, the others nothing
    int bonded = 0;
    for (std::size_t p = 0; p < fixed.particles.size(); ++p) {
      EXPECT_EQ(fixed.layer_data.particles.inv_t[p], fixed.layer_data.particles.bonded[p] ? 1.0 / 2e-6 : 0.0);
      bonded += fixed.layer_data.particles.bonded[p];
    }
    EXPECT_GT(bonded, 0);
    Scene<2> elapsed = test::scene_from(binder_deck(c.T, "\"elapsed\""));
    LayerLaw e = elapsed.contact.layers[0];
    e.at_time(100e-6);
    EXPECT_NEAR(e.kt / l.kt, 1.0, 0.005) << c.T;
    EXPECT_NEAR(e.kn / l.kn, 1.0, 0.005) << c.T;
  }
}

namespace {
std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
double json_number(const std::string& text, const std::string& key) {
  const auto at = text.find("\"" + key + "\":");
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + key.size() + 3));
}
}  // namespace

// The quick study's densest run (porosity 0.053, 20 um cells, the binder layer of the paper decks
// on every grain contact, three grain fields meeting at the left die wall) reaches its end strain
// quasi-statically. With the rigid bodies acting before the springs after the grid update it did
// not: from 3.13 % strain a spring-wall fight grew (KE/IE 0.001 -> 0.07 in 80 steps) until a TATB
// particle was crushed past its EOS at step 7514.
TEST(BinderLayer, DensestQuickRunStaysQuasiStaticAndBalancesItsForces) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_layer053_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string cmd = fmt::format(
      "OMP_NUM_THREADS=1 {} study {}/paper/quick.toml --out {} --only density-0.053-s1 --threads 1 --quiet "
      "> {} 2>&1",
      PBXMPM_BINARY, PBXMPM_EXAMPLES_DIR, (dir / "study").string(), (dir / "log").string());
  EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "log");
  const fs::path run = dir / "study" / "runs" / "density-0.053-s1";
  EXPECT_NE(slurp(run / "run.json").find("\"status\": \"finished\""), std::string::npos) << slurp(dir / "log");
  const std::string analysis = slurp(run / "analysis.json");
  const double ke_ie = json_number(analysis, "ke_ie_max_from_window_start");
  EXPECT_LT(ke_ie, 0.05) << "the run's own quasi-static limit, from where the moduli are read to the end";

  // Newton's laws on the whole paper specimen, every history row after the first: the external
  // forces (the walls' and the punch's reactions, each averaged over the row's interval from the
  // exact impulses the rigid contact applied) equal the rate of change of the specimen's momentum
  // over that interval, per axis; the grain-grain films and contacts are internal and must cancel.
  // Measured 5e-9 of the punch force (round-off of the sums); a film impulse booked on one side
  // only, or a rigid reaction not equal to the impulse applied, breaks it by percents. The mass is
  // constant to the bit, and the frictionless walls and punch (base.toml: wall_friction = 0) carry
  // no tangential force.
  std::ifstream h(run / "history.csv");
  std::string line;
  std::getline(h, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) names.push_back(c);
  }
  const auto col = [&](const char* name) {
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) return c;
    ADD_FAILURE() << "history.csv has no column " << name;
    return std::size_t{0};
  };
  std::vector<std::vector<double>> rows;
  while (std::getline(h, line)) {
    std::vector<double> r;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) r.push_back(std::stod(c));
    rows.push_back(r);
  }
  ASSERT_GT(rows.size(), 50u);
  const std::size_t t = col("t_s"), px = col("momentum_x_N_s_per_m"), py = col("momentum_y_N_s_per_m"),
                    mass = col("mass_kg_per_m"), punch_y = col("punch_fy_N_per_m");
  const char* walls[] = {"wall_left", "wall_right", "wall_bottom", "punch"};
  double worst = 0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto &a = rows[k - 1], &b = rows[k];
    double fx = 0, fy = 0;
    for (const char* w : walls) {
      fx += b[col(fmt::format("{}_fx_N_per_m", w).c_str())];
      fy += b[col(fmt::format("{}_fy_N_per_m", w).c_str())];
    }
    const double dt = b[t] - a[t], scale = std::abs(b[punch_y]);
    if (!(scale > 0)) continue;
    worst = std::max({worst, std::abs(fx - (b[px] - a[px]) / dt) / scale, std::abs(fy - (b[py] - a[py]) / dt) / scale});
    EXPECT_EQ(b[mass], rows[0][mass]) << "row " << k;
    for (const char* tangential :
         {"wall_left_fy_N_per_m", "wall_right_fy_N_per_m", "wall_bottom_fx_N_per_m", "punch_fx_N_per_m"})
      EXPECT_EQ(b[col(tangential)], 0.0) << tangential << ", row " << k;
  }
  EXPECT_LT(worst, 1e-6) << "external force against the momentum's rate of change, relative to the punch force";
  fs::remove_all(dir);
}

// A spring reads its jump from particle sums (a weighted mean of the nodal displacements around the
// node) and so must hand its impulse back through the same particles: applied at the node alone it is
// a non-symmetric stiffness, which made energy on the paper specimen. The quick 293 K specimen
// (examples/paper/base.toml at 20 um cells) to 0.4 % strain: kinetic energy plus stress work over the
// punch work, at most over the rows from 0.1 % on, is 1.06 through the particles (the default) and
// 1.23 at the node ("node", the code until 2026-12-06); the limits 1.08 and 1.15 tell them apart.
TEST(BinderLayer, SpringsHandedThroughTheParticlesKeepTheSpecimensEnergyBalance) {
  namespace fs = std::filesystem;
  auto worst_ratio = [](const std::string& transfer) {
    const fs::path dir = fs::temp_directory_path() / ("pbxmpm_transfer_" + transfer + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string cmd = fmt::format(
        "{} run {}/paper/base.toml --out {} --threads 1 --quiet --set 'grid.cell_size=\"20 um\"' "
        "--set run.end_strain=0.004 --set run.snapshots=0 {} > {}.log 2>&1",
        PBXMPM_BINARY, PBXMPM_EXAMPLES_DIR, dir.string(),
        transfer.empty() ? std::string() : "--set 'contact.spring_transfer=\"" + transfer + "\"'", dir.string());
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(fs::path(dir.string() + ".log"));
    std::ifstream h(dir / "history.csv");
    std::string line, cell;
    std::getline(h, line);
    std::vector<std::string> names;
    for (std::stringstream ss(line); std::getline(ss, cell, ',');) names.push_back(cell);
    auto col = [&](const std::string& name) {
      const auto it = std::find(names.begin(), names.end(), name);
      EXPECT_NE(it, names.end()) << name;
      return static_cast<std::size_t>(it - names.begin());
    };
    const std::size_t e = col("strain"), k = col("kinetic_J_per_m"), ie = col("internal_J_per_m"),
                      w = col("punch_work_J_per_m");
    double worst = 0;
    while (std::getline(h, line)) {
      std::vector<double> r;
      for (std::stringstream ss(line); std::getline(ss, cell, ',');) r.push_back(std::stod(cell));
      if (r.size() == names.size() && r[e] >= 0.001 && r[w] > 0) worst = std::max(worst, (r[k] + r[ie]) / r[w]);
    }
    fs::remove_all(dir);
    fs::remove(dir.string() + ".log");
    return worst;
  };
  // the deck's default (no --set): the transfer through the particles
  const double particles = worst_ratio(""), node = worst_ratio("node");
  std::fprintf(stderr,
               "(KE + IE) / W, max from 0.1 %% to 0.4 %% strain: through the particles %.3f, at the node %.3f\n",
               particles, node);
  EXPECT_LT(particles, 1.08);
  EXPECT_GT(particles, 0.8);  // the run did load the specimen
  EXPECT_GT(node, 1.15);      // the control: the test sees the difference
}

// thickness = "coats": every bonded particle carries 1/t of its contact with t = coat_scale x the
// two grains' coats. On the paper specimen (20 um cells): doubling coat_scale halves every 1/t
// exactly and bonds the same particles (bond_gap fixed); each 1/t lies between the thickest and
// the thinnest pair the packing can make, and the contacts differ (coarse-coarse against
// fine-fine pairs: the spread of 1/t exceeds 2, which one uniform thickness would not give).
TEST(BinderLayer, CoatThicknessesComeFromEachContactsGrains) {
  std::string base = slurp(std::filesystem::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml");
  base.replace(base.find("cell_size = \"10 um\""), 19, "cell_size = \"20 um\"");
  base.replace(base.find("\nfilm = \"integrated\"") + 1, 19, "bond_gap = \"2 um\"");  // the uniform film: t per contact
  const auto scene_with = [&](const char* scale) {
    std::string d = base;
    d.replace(d.find("coat_scale = 1.64"), 17, std::string("coat_scale = ") + scale);
    return test::scene_from(d);
  };
  const Scene<2> one = scene_with("1.0"), two = scene_with("2.0");
  ASSERT_EQ(one.particles.size(), two.particles.size());
  ASSERT_TRUE(one.packing_stats.has_value());
  const double cmin = one.packing_stats->coat_min, cmax = one.packing_stats->coat_max;
  double lo = 1e300, hi = 0;
  int bonded = 0;
  for (std::size_t p = 0; p < one.particles.size(); ++p) {
    ASSERT_EQ(one.layer_data.particles.bonded[p], two.layer_data.particles.bonded[p]) << p;
    const double a = one.layer_data.particles.inv_t[p], b = two.layer_data.particles.inv_t[p];
    if (!one.layer_data.particles.bonded[p]) {
      EXPECT_EQ(a, 0.0);
      continue;
    }
    ++bonded;
    EXPECT_NEAR(b / a, 0.5, 1e-12) << p;
    EXPECT_GE(a, 1.0 / (2.0 * cmax) * (1 - 1e-12)) << p;
    EXPECT_LE(a, 1.0 / (2.0 * cmin) * (1 + 1e-12)) << p;
    lo = std::min(lo, a), hi = std::max(hi, a);
  }
  EXPECT_GT(bonded, 100);
  EXPECT_GT(hi / lo, 2.0);
}

// Without rigid bodies the mass-centre sums the layer's jump is read from must still be scattered:
// two bonded slabs at rest in free space stay at rest. Before, with no [die] or [[rigid]], the
// offsets were left at zero and every node read a fixed jump of 0.75 cells, which pushed the slabs
// apart (here D_n x 7.5 um = 7.5 MPa of traction from the first step).
TEST(BinderLayer, BondedSlabsAtRestStayAtRestWithoutRigidBodies) {
  const std::string deck = R"(
[run]
end_time = "2 us"
snapshots = 0
history_points = 20
[grid]
cell_size = "10 um"
min = ["-0.05 mm", "-0.05 mm"]
max = ["0.15 mm", "0.25 mm"]
[solver]
mass_scaling = 1
[materials.block]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
)" + two_slabs(0.1, 100, 0.2, 1e12, 3e11);
  Scene<2> sc = test::scene_from(deck);
  ASSERT_TRUE(sc.bodies.empty());
  Runner<2> r(sc, test::quiet());
  double ke_max = 0;
  r.run([&](const Measurement& m) { ke_max = std::max(ke_max, m.kinetic); });
  ASSERT_GT(r.solver().step_count(), 50);
  // 7.5 MPa over 2 us on a 0.1 mm slab moves it at ~40 m/s: kinetic energy ~ 1e-2 J/m; at rest it is
  // round-off
  EXPECT_LT(ke_max, 1e-12) << "slabs at rest started to move";
}

namespace {
// A disk of radius 100 um (field "upper") resting on a flat slab (field "lower"), the two joined
// by the layer law with a linear-elastic film (E = 1 GPa, nu = 0: M = 1 GPa, G = 0.5 GPa) of
// thickness t = 10 um (t/R = 0.1, as the paper specimen's pairs: t = 0.052 d); no die.
std::string disk_on_flat(double h_um, const std::string& film) {
  return fmt::format(R"(
[run]
end_time = "1 us"
snapshots = 0
history_points = 2
[grid]
cell_size = "{0} um"
min = ["-0.16 mm", "-0.08 mm"]
max = ["0.16 mm", "0.24 mm"]
[solver]
mass_scaling = 1
[materials.body]
model = "linear_elastic"
density = "2 g/cm3"
youngs_modulus = "25 GPa"
poisson_ratio = 0.25
[materials.film]
model = "linear_elastic"
density = "2 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.0
[contact]
default = "frictionless"
[[contact.pair]]
materials = ["body", "body"]
law = "binder_layer"
friction = 0.3
shear_cap = "none"
binder = "film"
thickness = "10 um"
{1}
[[geometry]]
min = ["-0.12 mm", "-0.04 mm"]
max = ["0.12 mm", "0 mm"]
material = "body"
field = "lower"
[[geometry]]
shape = "disk"
center = ["0 mm", "0.1 mm"]
radius = "0.1 mm"
material = "body"
field = "upper"
)",
                     h_um, film.empty() ? std::string() : "film = \"" + film + "\"");
}

// The film's vertical stiffness per unit depth: the upper body moved down rigidly by delta, one
// step from rest; the impulse the layer gives it over that step, over dt and delta.
double disk_on_flat_stiffness(double h_um, const std::string& film) {
  Scene<2> sc = test::scene_from(disk_on_flat(h_um, film));
  const double delta = 0.05e-6;
  int upper = -1;
  for (std::size_t f = 0; f < sc.field_names.size(); ++f)
    if (sc.field_names[f] == "upper") upper = static_cast<int>(f);
  EXPECT_GE(upper, 0);
  for (std::size_t p = 0; p < sc.particles.size(); ++p)
    if (sc.particles.field[p] == upper) sc.particles.x[p].y() -= delta;
  Solver<2> s(sc);
  s.step();
  double py = 0;
  for (std::size_t p = 0; p < sc.particles.size(); ++p)
    if (sc.particles.field[p] == upper) py += sc.particles.mass[p] * sc.particles.v[p].y();
  return py / s.dt() / delta;
}
}  // namespace

// A thin film between a curved grain and its neighbour is a bed of springs whose thickness grows
// with the gap between the surfaces, t + g(x), g = R - sqrt(R^2 - x^2) for a disk on a flat, so
// its vertical stiffness per unit depth is (thin film, Winkler) k = int M / (t + g(x)) dx = 9.88 M
// here (tilting each spring to the mean of the two surfaces' normals and adding its shear part
// gives 2.6 % less). The grid can carry a spring only where the two bodies share nodes, a band
// about a cell wide around the contact point:
// - with one thickness t on that band (film = "uniform", the default) the stiffness is M/t times
//   the band's width, which shrinks with the cell: measured 0.62, 0.41, 0.28 k at 10, 5, 2.5 um;
// - with film = "integrated" each contact gets its whole film, sum a/(t + g) over the particles
//   facing the other body out to 4t, spread over the band: 0.74, 0.78, 0.94 k (2026-12-05). The
//   rest is the band's springs acting along their own normals, tilted by up to 24 degrees at 10 um
//   cells, while the sum is taken along each particle's own gap.
TEST(BinderLayer, FilmOnACurvedContactIntegratesOneOverTheLocalThickness) {
  const double R = 100e-6, t = 10e-6, M = 1e9;
  double closed = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = -R + (i + 0.5) * 2.0 * R / n, g = R - std::sqrt(R * R - x * x);
    closed += M / (t + g) * 2.0 * R / n;
  }
  double lo = 1e300, hi = 0;
  for (const double h : {10.0, 5.0, 2.5}) {
    const double k = disk_on_flat_stiffness(h, "integrated") / closed,
                 k_uniform = disk_on_flat_stiffness(h, "") / closed;
    std::fprintf(stderr, "cell %.1f um: film integrated k/closed %.3f, uniform k/closed %.3f\n", h, k, k_uniform);
    EXPECT_GT(k, 0.70) << h;  // the figures above, to a few percent
    EXPECT_LT(k, 1.05) << h;
    lo = std::min(lo, k), hi = std::max(hi, k);
    if (h == 2.5) {
      EXPECT_NEAR(k, 1.0, 0.08) << "film resolved by the band";
    }
  }
  EXPECT_LT(hi / lo, 1.35) << "the integrated film depends on the cell size";
}

// film = "bonds" carries the same film on particle pairs: each particle facing the other body ties to
// its nearest particle there with half the film under its patch, so the sum is the Winkler integral
// resolved by the particle spacing, not by the band of nodes the two bodies share (the integral is
// taken where the film reaches, g <= film_extent x t).
TEST(BinderLayer, BondedPairsCarryTheWholeFilmOnACurvedContact) {
  const double R = 100e-6, t = 10e-6, M = 1e9;
  double closed = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = -R + (i + 0.5) * 2.0 * R / n, g = R - std::sqrt(R * R - x * x);
    if (g <= 4.0 * t) closed += M / (t + g) * 2.0 * R / n;  // the film reaches film_extent x t (4 t)
  }
  for (const double h : {10.0, 5.0, 2.5}) {
    const double k = disk_on_flat_stiffness(h, "bonds") / closed;
    std::fprintf(stderr, "cell %.1f um: film bonds k/closed %.3f\n", h, k);
    // measured 0.951, 0.979, 1.001 (2026-12-07): the sum over particle patches of a curved surface
    EXPECT_NEAR(k, 1.0, h == 2.5 ? 0.01 : 0.06) << h;
  }
}

// On a flat contact every facing particle has gap 0, so film = "integrated" carries exactly 1/t:
// the layered column in the die (a linear-elastic film, t = 2 um, D_n H/M = 0.1 at 10 um cells)
// gives the punch stress history of film = "uniform" to 0.5 % of its end value in every row (0.18 %
// measured 2026-12-05; the
// two bond slightly different particle sets: integrated touches within one cell, uniform within
// one spacing; the test prints the largest difference).
TEST(BinderLayer, IntegratedFilmOnAFlatContactIsTheUniformFilm) {
  const auto history = [](const char* film) {
    std::string d = column_deck(240.0, 1.0, 1.0);
    const std::size_t at = d.find("normal_stiffness");
    d = d.substr(0, at) + fmt::format("binder = \"film\"\nthickness = \"2 um\"\nfilm = \"{}\"\n", film);
    d += R"(
[materials.film]
model = "linear_elastic"
density = "2 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
)";
    Scene<2> sc = test::scene_from(d);
    Runner<2> r(sc, test::quiet());
    std::vector<double> s;
    r.run([&](const Measurement& m) { s.push_back(m.punch_stress); });
    return s;
  };
  const auto uniform = history("uniform"), integrated = history("integrated"), bonds = history("bonds");
  ASSERT_EQ(uniform.size(), integrated.size());
  ASSERT_GT(uniform.back(), 1e6);
  double worst = 0;
  for (std::size_t k = 0; k < uniform.size(); ++k)
    worst = std::max(worst, std::abs(integrated[k] - uniform[k]) / uniform.back());
  std::fprintf(stderr, "integrated vs uniform film on a flat contact: largest difference %.3f %% of the end stress\n",
               100 * worst);
  EXPECT_LT(worst, 5e-3);
  // film = "bonds" carries the same film on the particle pairs across it (0.13 % measured 2026-12-07)
  ASSERT_EQ(uniform.size(), bonds.size());
  double worst_bonds = 0;
  for (std::size_t k = 0; k < uniform.size(); ++k)
    worst_bonds = std::max(worst_bonds, std::abs(bonds[k] - uniform[k]) / uniform.back());
  std::fprintf(stderr, "bonds vs uniform film on a flat contact: largest difference %.3f %% of the end stress\n",
               100 * worst_bonds);
  EXPECT_LT(worst_bonds, 5e-3);
}

namespace {
// A disk (R = 100 um, field "disk") pressed in the die between two slabs, joined to each by a 4 um
// binder film, with a 5 um strip of resolved binder particles on the lower slab beside each of its
// contacts, where the disk curves away within the film's reach: the binder particles sit in the
// bonded gap. Everything linear elastic, Coulomb mu = 0.3 between the binder and the bodies; 10 um
// cells, to 1 % strain.
std::string disk_between_slabs(const std::string& film, const std::string& gap_binder = "") {
  return fmt::format(R"(
[run]
end_strain = 0.01
history_points = 50
[grid]
cell_size = "10 um"
particles_per_cell = 2
[solver]
cfl = 0.4
mass_scaling = 10
[die]
width = "0.24 mm"
height = "0.32 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.0005
[materials.body]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[materials.film]
model = "linear_elastic"
density = "2 g/cm3"
youngs_modulus = "0.2 GPa"
poisson_ratio = 0.38
[materials.binder]
model = "linear_elastic"
density = "2 g/cm3"
youngs_modulus = "0.2 GPa"
poisson_ratio = 0.38
[contact]
default = "coulomb"
friction = 0.3
[[contact.pair]]
materials = ["body", "body"]
law = "binder_layer"
friction = 0.3
shear_cap = "none"
binder = "film"
thickness = "4 um"
film = "{}"
{}
[[geometry]]
min = ["0.02 mm", "0.06 mm"]
max = ["0.09 mm", "0.065 mm"]
material = "binder"
[[geometry]]
min = ["0.15 mm", "0.06 mm"]
max = ["0.22 mm", "0.065 mm"]
material = "binder"
[[geometry]]
min = ["0 mm", "0 mm"]
max = ["0.24 mm", "0.06 mm"]
material = "body"
field = "lower"
[[geometry]]
shape = "disk"
center = ["0.12 mm", "0.16 mm"]
radius = "0.1 mm"
material = "body"
field = "disk"
[[geometry]]
min = ["0 mm", "0.26 mm"]
max = ["0.24 mm", "0.32 mm"]
material = "body"
field = "upper"
)",
                     film, gap_binder.empty() ? std::string() : "gap_binder = \"" + gap_binder + "\"");
}

// (KE + IE)/W of the disk between slabs, worst row's distance from 1 from 0.1 % strain on
double worst_energy_balance(Scene<2>& sc, const char* what) {
  Runner<2> r(sc, test::quiet());
  double worst = 0, last = 0;
  int rows = 0;
  r.run([&](const Measurement& m) {
    if (m.strain < 1e-3 || m.punch_work <= 0.0) return;
    const double balance = (m.kinetic + m.internal) / m.punch_work;
    worst = std::max(worst, std::abs(balance - 1.0));
    last = balance;
    ++rows;
  });
  std::fprintf(stderr, "disk between slabs, %s: (KE + IE)/W at the end %.4f, worst row off by %.4f over %d rows\n",
               what, last, worst, rows);
  EXPECT_GT(rows, 30) << what;
  return worst;
}
}  // namespace

// film = "integrated" with gap_binder = "join": the binder particles in the bonded gaps join a grain
// as with the pairs, the film stays at the nodes, and the energy balance that the free gap binder
// breaks (crushed between the two fields the bonded nodes let overlap) holds.
TEST(BinderLayer, IntegratedFilmWithJoinedGapBinderBalancesItsEnergy) {
  Scene<2> joined = test::scene_from(disk_between_slabs("integrated", "join"));
  Scene<2> free = test::scene_from(disk_between_slabs("integrated"));
  EXPECT_TRUE(joined.layer_data.bonds.empty());  // the pairs served the join only
  EXPECT_GT(joined.layer_data.gap_particles_joined, 5);
  EXPECT_LT(joined.layer_data.gap_particles_joined, 40);
  EXPECT_EQ(free.layer_data.gap_particles_joined, 0);
  const double w_joined = worst_energy_balance(joined, "integrated, gap binder joined");
  const double w_free = worst_energy_balance(free, "integrated, gap binder free");
  // measured 2026-12-08: worst row 0.057 joined, 0.138 free (both 0.969 at 1 %; the node film's
  // springs are not exactly work-conjugate, docs/theory/contact.md): without the join the first fails
  EXPECT_LT(w_joined, 0.08);
  EXPECT_GT(w_free, 0.1);
}

// gap_binder is a property of a film that finds pairs: refused with the uniform film, and its words
// are checked.
TEST(BinderLayer, GapBinderNeedsAnIntegratedFilmAndAKnownWord) {
  for (const auto& [film, gap, says] : {std::tuple{"uniform", "join", "applies only with film"},
                                        std::tuple{"integrated", "joined", "must be 'join' or 'free'"}}) {
    try {
      test::scene_from(disk_between_slabs(film, gap));
      ADD_FAILURE() << film << " " << gap << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("gap_binder"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

// With film = "bonds" the binder particles in a bonded gap join the nearer grain's field, so the
// film is counted once: kinetic energy plus stress work (the springs' energy included) equals the
// punch work, 0.998-1.000 in every row from 0.1 % strain (measured 2026-12-07). Left in their own
// field they met both bodies by Coulomb contact and were crushed between the two fields the bonded
// nodes let overlap: 0.99 at 0.1 % growing to 1.50 at 1 %, so the test's 2 % fails without the join.
TEST(BinderLayer, BondedGapsBinderParticlesJoinAGrainAndTheEnergyBalances) {
  Scene<2> sc = test::scene_from(disk_between_slabs("bonds"));
  EXPECT_GT(sc.layer_data.gap_particles_joined, 5);
  EXPECT_LT(sc.layer_data.gap_particles_joined, 40);  // the strips' 28 particles near the disk, not the slabs
  EXPECT_LT(worst_energy_balance(sc, "film bonds"), 0.02);
}

// A pair joins two particles that a run over MPI ranks could hand to different ranks: a rank's
// share of such a scene is refused with the reason, not stepped with pairs pointing elsewhere.
TEST(BinderLayer, BondedPairsAreRefusedInARunOverRanks) {
  Scene<2> sc = test::scene_from(disk_between_slabs("bonds"));
  ASSERT_FALSE(sc.layer_data.bonds.empty());
  try {
    keep_particle_range(sc, 0, sc.particles.size() / 2);
    FAIL() << "a rank's share of a scene with film = \"bonds\" was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("film = \"bonds\" is not built for a run over MPI ranks"), std::string::npos)
        << e.what();
  }
}

// The automatic bonded zone of a layer with a thickness: closure x t + one cell. A 12 um binder
// layer (F2314 at 293 K, secant over 100 us) in the column at 5 um cells closes by about 9 um (1.8
// cells) at 3 % strain, short of its squeeze-out at 12 um; the automatic zone (17 um) gives the
// punch stress of a zone twice as deep (30 um) at every row from 1 % within 0.5 % (measured
// 2026-12-06: identical), where the two cells of before (10 um) let the pair turn to Coulomb
// contact: 7.9 % off.
TEST(BinderLayer, AutomaticBondedZoneCoversTheLayersClosure) {
  auto deck = [](const char* depth) {
    std::string d = binder_deck(293, "\"100 us\"");
    d.replace(d.find("thickness = \"2 um\""), 18, "thickness = \"12 um\"");
    d.replace(d.find("end_strain = 0.06"), 17, "end_strain = 0.03");
    d.replace(d.find("mass_scaling = 100"), 18, "mass_scaling = 10");
    const std::string cell = "cell_size = \"10 um\"";
    d.replace(d.find(cell), cell.size(), "cell_size = \"5 um\"");
    if (*depth) d.insert(d.find("thickness = \"12 um\""), fmt::format("bond_depth = \"{}\"\n", depth));
    return d;
  };
  auto curve = [](const std::string& d) {
    Scene<2> sc = test::scene_from(d);
    Runner<2> r(sc, test::quiet());
    std::vector<Row> rows;
    r.run([&](const Measurement& m) { rows.push_back({m.strain, m.punch_stress}); });
    return rows;
  };
  const auto automatic = curve(deck("")), deep = curve(deck("30 um")), shallow = curve(deck("10 um"));
  ASSERT_EQ(automatic.size(), deep.size());
  double worst = 0, worst_shallow = 0;
  for (std::size_t i = 0; i < deep.size(); ++i) {
    if (deep[i].strain < 0.01) continue;
    worst = std::max(worst, std::abs(automatic[i].stress / deep[i].stress - 1));
    worst_shallow = std::max(worst_shallow, std::abs(shallow[i].stress / deep[i].stress - 1));
  }
  std::fprintf(stderr, "punch stress against a 30 um zone: automatic within %.2f %%, two cells %.2f %%\n", 100 * worst,
               100 * worst_shallow);
  EXPECT_LT(worst, 0.005);
  EXPECT_GT(worst_shallow, 0.03);  // the mechanism the rule is for
}
