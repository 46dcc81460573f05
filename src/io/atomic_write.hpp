#pragma once
// A text file replaced whole or not at all: written under FILE.tmp, checked, then renamed over
// FILE. A reader (a report made while the run goes) or a run killed mid-write never sees half a
// file; a failed write (full disk) throws InputError naming the file and leaves the old one.
#include <filesystem>
#include <string>

namespace pbx {

void write_text_atomically(const std::filesystem::path& file, const std::string& text);

}  // namespace pbx
