#include "io/atomic_write.hpp"

#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    f.close();
    if (!f) throw InputError(fmt::format("cannot write '{}'", tmp.string()));
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace pbx
