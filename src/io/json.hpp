#pragma once
// JSON for the project's small result files (run.json, study.json, analysis.json, fits.json,
// packing.json): nlohmann-json's document model, keys kept in insertion order so that a written file
// reads in a meaningful order. The helpers below add what a result file needs on top of the
// library: typed reads whose error names the value, errors that name the file, and whole-or-absent
// writes.
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace pbx {

using Json = nlohmann::ordered_json;

// Typed reads; `what` names the value in the InputError thrown on a type mismatch. A number is
// any JSON number (integer or not); null is not a number.
bool json_bool(const Json& j, std::string_view what = "value");
double json_number(const Json& j, std::string_view what = "value");
const std::string& json_string(const Json& j, std::string_view what = "value");
const Json& json_array(const Json& j, std::string_view what = "value");
const Json& json_object(const Json& j, std::string_view what = "value");

// The member `key` of an object, or nullptr when absent or when `j` is not an object.
const Json* json_find(const Json& j, std::string_view key);

// Anything else would convert to a Json silently (a std::string becomes a JSON string, whose
// members are never found): refused at compile time.
template <class T>
bool json_bool(const T&, std::string_view = {}) = delete;
template <class T>
double json_number(const T&, std::string_view = {}) = delete;
template <class T>
const std::string& json_string(const T&, std::string_view = {}) = delete;
template <class T>
const Json& json_array(const T&, std::string_view = {}) = delete;
template <class T>
const Json& json_object(const T&, std::string_view = {}) = delete;
template <class T>
const Json* json_find(const T&, std::string_view) = delete;
template <class T>
std::string json_dump(const T&) = delete;

// An array of doubles; non-finite entries are written as null (JSON has no NaN).
Json json_numbers(const std::vector<double>& xs);

// Two-space indentation, arrays of numbers on one line, integral numbers without ".0"; invalid
// UTF-8 in strings is replaced (U+FFFD) rather than thrown at write time, so that a message read
// from a file or the OS can never lose a result file.
std::string json_dump(const Json& j);
// Parse errors are InputErrors naming `source`, its line and column.
Json json_parse(const std::string& text, const std::string& source = "<json>");
Json json_read_file(const std::string& path);
// Written whole or not at all (temporary, fsync, rename): these are result files.
void json_write_file(const std::string& path, const Json& j);

}  // namespace pbx
