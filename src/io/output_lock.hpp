#pragma once
// One writer per output folder. Two processes writing one run folder (or one study folder)
// interleave their history rows and checkpoints into files that look valid and are not; the
// second one is refused at the start instead. The lock is an flock(2) on DIR/.pbxmpm.lock, so it
// ends with the process that holds it, however that process ends (a killed run leaves no stale
// lock behind); the file holds the holder's pid for the message.
#include <filesystem>
#include <string>

namespace pbx {

class OutputLock {
 public:
  OutputLock() = default;
  // Creates `dir` if needed and locks it; throws InputError naming the folder and the pid that
  // holds it. `what` says what is being written ("run", "study") for the message.
  OutputLock(const std::filesystem::path& dir, const std::string& what);
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  OutputLock(OutputLock&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  OutputLock& operator=(OutputLock&& o) noexcept;
  ~OutputLock();
  bool held() const { return fd_ >= 0; }
  static constexpr const char* kFile = ".pbxmpm.lock";

 private:
  int fd_ = -1;
};

}  // namespace pbx
