// Output files fail loudly and one writer owns a folder: a history row that cannot be written
// (disk full) stops the run with the file's name instead of going missing, and a second process
// is refused a folder another one is writing (its rows would interleave with the first's).
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "input_error_message.hpp"
#include "io/csv_writer.hpp"
#include "io/output_lock.hpp"

namespace fs = std::filesystem;
using namespace pbx;

using pbx::test::message_of;

// /dev/full accepts the open and fails every write with ENOSPC, as a full disk does.
TEST(OutputFiles, CsvRowsThatCannotBeWrittenAreErrorsNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string header = pbx::test::output_error_of([] { CsvWriter w("/dev/full", {"t_s", "strain"}); });
  EXPECT_NE(header.find("cannot write '/dev/full'"), std::string::npos) << header;
  EXPECT_NE(header.find("No space left"), std::string::npos) << header;
  CsvWriter append("/dev/full", {"t_s", "strain"}, true);  // a restart appends: no header is written
  const std::string row = pbx::test::output_error_of([&] { append.row({0.0, 0.0}); });
  EXPECT_NE(row.find("cannot write a row to '/dev/full'"), std::string::npos) << row;
}

// flock conflicts between two open file descriptions even within one process, so the second
// writer can be played here; the lock ends with its holder.
TEST(OutputFiles, ASecondWriterIsRefusedTheFolderUntilTheFirstEnds) {
  const fs::path dir = fs::temp_directory_path() / ("pbx_test_lock_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    OutputLock first(dir, "run");
    ASSERT_TRUE(first.held());
    const std::string second = message_of([&] { OutputLock again(dir, "run"); });
    EXPECT_NE(second.find("another pbxmpm process (pid " + std::to_string(::getpid()) + ") is writing to '" +
                          dir.string() + "'"),
              std::string::npos)
        << second;
    EXPECT_NE(second.find("give this run another output folder"), std::string::npos) << second;
  }
  // the lock file stays (removing it would race a third process); it no longer locks
  EXPECT_TRUE(fs::exists(dir / OutputLock::kFile));
  EXPECT_EQ(message_of([&] { OutputLock next(dir, "run"); }), "");
  fs::remove_all(dir);
}
