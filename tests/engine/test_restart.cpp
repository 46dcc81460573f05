// A run restarted from a checkpoint ends with the same history.csv, byte for byte, as the
// uninterrupted run (the checkpoint holds particles, histories, clock and reporting state).
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "block_deck.hpp"
#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "scene_fixture.hpp"

namespace fs = std::filesystem;
using namespace pbx;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
}  // namespace

TEST(Restart, RestartedRunEqualsUninterruptedRun) {
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_restart_" + std::to_string(::getpid()));
  const std::string deck = test::block_deck(100, 0.01);
  RunOptions o = test::quiet();
  o.out_dir = (dir / "a").string();
  o.deck_text = deck;
  o.deck_name = "block";
  o.checkpoint_every = 70;  // rows 70 and 140 of 201: the file keeps the one at row 140
  {
    Scene<2> sc = test::scene_from(deck);
    Runner<2> r(sc, o);
    r.run();
  }
  ASSERT_TRUE(fs::exists(dir / "a" / "checkpoint.h5"));
  // "interrupted" copy: the checkpoint plus the full history, which the restart must truncate
  fs::create_directories(dir / "b");
  fs::copy_file(dir / "a" / "history.csv", dir / "b" / "history.csv");
  const CheckpointData c = read_checkpoint((dir / "a" / "checkpoint.h5").string());
  EXPECT_EQ(c.scalars.at("rows_written"), 140);
  {
    Scene<2> sc = test::scene_from(c.deck_text);
    RunOptions ob = o;
    ob.out_dir = (dir / "b").string();
    ob.checkpoint_every = 0;
    Runner<2> r(sc, ob, true);
    r.resume(c);
    r.run();
  }
  EXPECT_EQ(slurp(dir / "a" / "history.csv"), slurp(dir / "b" / "history.csv"));
  EXPECT_THROW(read_checkpoint((dir / "a" / "history.csv").string()), InputError);
  // A history written by a version with other columns is refused, not appended to with rows that
  // do not match its header.
  {
    fs::create_directories(dir / "c");
    std::string text = slurp(dir / "a" / "history.csv");
    text.insert(text.find('\n'), ",an_old_column");
    std::ofstream(dir / "c" / "history.csv") << text;
    Scene<2> sc = test::scene_from(c.deck_text);
    RunOptions oc = o;
    oc.out_dir = (dir / "c").string();
    oc.checkpoint_every = 0;
    Runner<2> r(sc, oc, true);
    try {
      r.resume(c);
      FAIL() << "a history with other columns must not be resumed";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("columns"), std::string::npos) << e.what();
    }
  }
  // The same particle count with other masses (here another density; in practice a re-packed
  // specimen) is refused: the checkpoint's particles would be resumed with the wrong grains.
  {
    fs::create_directories(dir / "d");
    fs::copy_file(dir / "a" / "history.csv", dir / "d" / "history.csv");
    std::string text = c.deck_text;
    text.replace(text.find("\"1.934 g/cm3\""), 13, "\"1.900 g/cm3\"");
    Scene<2> sc = test::scene_from(text);
    RunOptions od = o;
    od.out_dir = (dir / "d").string();
    od.checkpoint_every = 0;
    Runner<2> r(sc, od, true);
    try {
      r.resume(c);
      FAIL() << "a checkpoint of other particles must not be resumed";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("differ from the deck's at the same count"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}
