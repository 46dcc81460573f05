#include "io/atomic_write.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
[[noreturn]] void fail(const std::filesystem::path& file, const std::string& tmp, int fd, int err, const char* step) {
  if (fd >= 0) ::close(fd);
  ::unlink(tmp.c_str());
  throw OutputError(fmt::format("cannot write '{}': {} ({}); the previous file, if any, is kept", file.string(),
                                std::strerror(err), step));
}
}  // namespace

void write_bytes_atomically(const std::filesystem::path& file, const void* data, std::size_t size) {
  // A size limit (ulimit -f) raises SIGXFSZ, which kills the process by default: ignored, the
  // write fails with EFBIG and is reported like a full disk.
  std::signal(SIGXFSZ, SIG_IGN);
  const std::string tmp = file.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(file, tmp, -1, errno, "creating the temporary file");
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(file, tmp, fd, n < 0 ? errno : ENOSPC, "writing");
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  // the data on the disk before the name: a crash after the rename cannot leave a renamed empty file
  if (::fsync(fd) != 0) fail(file, tmp, fd, errno, "flushing to the disk");
  if (::close(fd) != 0) fail(file, tmp, -1, errno, "closing");
  if (std::rename(tmp.c_str(), file.c_str()) != 0) fail(file, tmp, -1, errno, "renaming the temporary file");
  // the rename itself durable; a folder that cannot be synced (some network file systems) is not an error
  const auto dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
  write_bytes_atomically(file, text.data(), text.size());
}

}  // namespace pbx
