#pragma once
// The message of the InputError a callable throws, or "" if it throws none: the tests of this
// folder check that bad input is refused with a message naming the key or file.
#include <functional>
#include <string>

#include "core/error.hpp"

namespace pbx::test {
inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
// The same for an OutputError (a file that could not be written).
inline std::string output_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace pbx::test
