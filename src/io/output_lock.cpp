#include "io/output_lock.hpp"

#include <cerrno>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

OutputLock::OutputLock(const std::filesystem::path& dir, const std::string& what) {
  std::filesystem::create_directories(dir);
  const std::string file = (dir / kFile).string();
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(fmt::format("cannot create the lock file '{}': {}", file, std::strerror(errno)));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char buf[32] = {};
    const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) {
      const std::string pid = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string("?");
      throw InputError(
          fmt::format("another pbxmpm process (pid {}) is writing to '{}'; wait for it to end, or "
                      "give this {} another output folder",
                      pid.substr(0, pid.find('\n')), dir.string(), what));
    }
    throw InputError(fmt::format("cannot lock '{}': {}", file, std::strerror(err)));
  }
  // the holder's pid, for the message a second process prints (informative only: the flock is the lock)
  const std::string pid = std::to_string(::getpid()) + "\n";
  // a lock file we cannot write the pid into still locks
  [[maybe_unused]] const bool noted = ::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) > 0;
}

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

}  // namespace pbx
