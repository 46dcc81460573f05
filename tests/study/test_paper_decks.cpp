// Every study deck shipped in examples/paper reads, and every run it defines is a valid deck: a
// mistyped override must fail here, not an hour into a study. Runs at the quick resolution are
// built in full (packing included); the fine and full decks differ from quick only in the cell
// size, so for them the run decks are parsed and their overrides checked against the base deck.
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "io/deck.hpp"
#include "solver/scene.hpp"
#include "study/study.hpp"

using namespace pbx;

namespace {
const std::string kPaper = std::string(PBXMPM_EXAMPLES_DIR) + "/paper/";

void build_every_run(const std::string& deck) {
  const StudySpec s = read_study(kPaper + deck);
  ASSERT_FALSE(s.runs.empty()) << deck;
  for (const auto& r : s.runs) {
    Deck d = Deck::from_string(run_deck_text(s, r), deck + ":" + r.id);
    EXPECT_NO_THROW({
      Scene<2> scene = build_scene<2>(d);
      d.check_unused();
    }) << deck << " run " << r.id;
  }
}
// The overrides of a run without those that set resolution and output only.
std::vector<std::pair<std::string, std::string>> physics_overrides(const StudyRunSpec& r) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& kv : r.set)
    if (kv.first != "grid.cell_size" && kv.first != "run.snapshots") out.push_back(kv);
  return out;
}
}  // namespace

TEST(PaperDecks, QuickStudyRunsAreValidDecks) { build_every_run("quick.toml"); }
TEST(PaperDecks, SensitivityStudyRunsAreValidDecks) { build_every_run("sensitivity.toml"); }
TEST(PaperDecks, ContactDetectionStudyRunsAreValidDecks) { build_every_run("contact_detection.toml"); }
TEST(PaperDecks, QuickLayerStudyRunsAreValidDecks) { build_every_run("quick_layer.toml"); }
TEST(PaperDecks, LayerResolutionStudyRunsAreValidDecks) { build_every_run("layer_resolution.toml"); }

TEST(PaperDecks, FineAndFullDifferFromQuickOnlyInResolution) {
  const StudySpec quick = read_study(kPaper + "quick.toml");
  for (const std::string name : {"fine.toml", "full.toml"}) {
    const StudySpec s = read_study(kPaper + name);
    ASSERT_EQ(s.runs.size(), quick.runs.size()) << name;
    for (std::size_t i = 0; i < s.runs.size(); ++i) {
      EXPECT_EQ(s.runs[i].id, quick.runs[i].id) << name;
      EXPECT_EQ(physics_overrides(s.runs[i]), physics_overrides(quick.runs[i])) << name << " " << s.runs[i].id;
    }
    EXPECT_EQ(s.analysis.window_lo, quick.analysis.window_lo) << name;
    EXPECT_EQ(s.analysis.window_hi, quick.analysis.window_hi) << name;
  }
}

TEST(PaperDecks, EnsembleIsTheQuickStudyOverFiveSeeds) {
  // ensemble.toml must stay the quick study (its seed-1 runs are quick's runs) with seeds 1-5 and
  // the same linear window; only snapshots may differ.
  const StudySpec quick = read_study(kPaper + "quick.toml");
  const StudySpec ens = read_study(kPaper + "ensemble.toml");
  ASSERT_EQ(ens.runs.size(), 5 * quick.runs.size());
  for (const auto& q : quick.runs) {
    int seeds = 0;
    for (const auto& r : ens.runs) {
      if (r.group != q.group || r.value_label != q.value_label) continue;
      ++seeds;
      auto strip_seed = [](std::vector<std::pair<std::string, std::string>> v) {
        std::erase_if(v, [](const auto& kv) { return kv.first == "specimen.seed"; });
        return v;
      };
      EXPECT_EQ(strip_seed(physics_overrides(r)), strip_seed(physics_overrides(q))) << r.id;
    }
    EXPECT_EQ(seeds, 5) << q.id;
  }
  EXPECT_EQ(ens.analysis.window_lo, quick.analysis.window_lo);
  EXPECT_EQ(ens.analysis.window_hi, quick.analysis.window_hi);
}
