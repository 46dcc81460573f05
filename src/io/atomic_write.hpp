#pragma once
// A file replaced whole or not at all: written under FILE.tmp, flushed to the disk (fsync),
// then renamed over FILE, and the folder synced. A reader (a report made while the run goes) or
// a run killed mid-write never sees half a file; a failed write (full disk, size limit) removes
// FILE.tmp, leaves FILE as it was, and throws OutputError naming FILE and the system's reason.
#include <cstddef>
#include <filesystem>
#include <string>

namespace pbx {

void write_bytes_atomically(const std::filesystem::path& file, const void* data, std::size_t size);
void write_text_atomically(const std::filesystem::path& file, const std::string& text);

}  // namespace pbx
