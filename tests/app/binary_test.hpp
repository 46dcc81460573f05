#pragma once
// Running the pbxmpm binary from a test: a shell command line with its output and exit code, and a
// fixture with a fresh folder per test (kept when the test fails, for a look).
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace pbx::test {

struct Result {
  int code = -1;       // exit code, or 128 + signal when the process was killed by one
  std::string output;  // stdout and stderr
};

// Runs a shell command line; "{pbx}" in it stands for the pbxmpm binary.
inline Result shell(const std::string& line) {
  std::string cmd = line;
  for (auto at = cmd.find("{pbx}"); at != std::string::npos; at = cmd.find("{pbx}"))
    cmd.replace(at, 5, fmt::format("'{}'", PBXMPM_BINARY));
  Result r;
  FILE* p = popen(("( " + cmd + " ) 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

// pbxmpm with these arguments.
inline Result pbxmpm(const std::string& args) { return shell("{pbx} " + args); }

class BinaryTest : public ::testing::Test {
 protected:
  explicit BinaryTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    if (!std::filesystem::exists(PBXMPM_BINARY)) GTEST_SKIP() << "pbxmpm is not built";
    dir = std::filesystem::temp_directory_path() / (prefix_ + std::to_string(::getpid()) + "_" +
                                                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
  std::filesystem::path dir;

 private:
  std::string prefix_;
};

}  // namespace pbx::test
