// End to end: `pbxmpm run` on the demo deck (refined to 10 um) (a homogeneous linear-elastic block compressed in the
// die, K = 10.59 GPa, G = 11.5 GPa) and then the analysis. Skipped when the pbxmpm binary has not
// been built (this test executable links only pbx_analysis).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "analysis/run_analysis.hpp"

using namespace pbx;
namespace fs = std::filesystem;

TEST(EngineBlock, HomogeneousElasticBlockInTheDieGivesBackKGE) {
  const fs::path exe = PBXMPM_BINARY;
  const fs::path deck = fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml";
  if (!fs::exists(exe) || !fs::exists(deck)) GTEST_SKIP() << "pbxmpm or the demo deck is not built/present";
  const fs::path out = fs::temp_directory_path() / ("pbx_test_engine_block_" + std::to_string(::getpid()));
  fs::remove_all(out);
  fs::create_directories(out);
  // The demo deck at 10 um cells: the punch reading converges at first order in the cell size
  // (its M is +1.2 % at the demo's 20 um, +0.43 % at 10 um, measured 2026-12-03), so at 10 um the
  // punch-derived moduli, the ones analysis.json reports first, meet the 1 % this test asks of them.
  std::stringstream text;
  text << std::ifstream(deck).rdbuf();
  std::string d = text.str();
  const std::string coarse = "cell_size = \"20 um\"";
  ASSERT_NE(d.find(coarse), std::string::npos) << "the demo deck's cell size changed: update this test";
  d.replace(d.find(coarse), coarse.size(), "cell_size = \"10 um\"");
  const fs::path fine = out / "block_10um.toml";
  std::ofstream(fine) << d;
  const std::string cmd = fmt::format("'{}' run '{}' -o '{}' -t 1 -q > /dev/null 2>&1", exe.string(), fine.string(),
                                      (out / "run").string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const Json a = analyze_run((out / "run").string(), AnalysisOptions{});
  auto at = [&](const char* block, const char* key) { return json_number(*json_find(*a.find(block), key)); };
  const double K = 10.59e9, G = 11.5e9, E = 9 * K * G / (3 * K + G);
  // The reported moduli (punch M, wall lambda) and the volume-averaged ones give the input K, G, E
  // to < 1 % (measured: punch K +0.46 %, G +0.41 %, E +0.42 %; volume averages +0.58 %).
  for (const char* block : {"moduli", "moduli_volume_average"}) {
    EXPECT_NEAR(at(block, "K_Pa") / K, 1.0, 0.01) << block;
    EXPECT_NEAR(at(block, "G_Pa") / G, 1.0, 0.01) << block;
    EXPECT_NEAR(at(block, "E_Pa") / E, 1.0, 0.01) << block;
    EXPECT_NEAR(at(block, "M_Pa") / (K + 4 * G / 3), 1.0, 0.01) << block;
  }
  // The side-wall reaction gives lambda = K - 2G/3 to < 1 %.
  EXPECT_NEAR(at("moduli", "lambda_Pa") / (K - 2 * G / 3), 1.0, 0.01);
  if (!HasFailure()) fs::remove_all(out);
}
