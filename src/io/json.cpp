#include "io/json.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"

namespace pbx {

namespace {

const char* type_name(const Json& j) {
  if (j.is_null()) return "null";
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  return "an object";
}

[[noreturn]] void mismatch(std::string_view what, const char* expected, const Json& j) {
  throw InputError(fmt::format("{}: expected {}, found {}", what, expected, type_name(j)));
}

}  // namespace

bool json_bool(const Json& j, std::string_view what) {
  if (!j.is_boolean()) mismatch(what, "a boolean", j);
  return j.get<bool>();
}
double json_number(const Json& j, std::string_view what) {
  if (!j.is_number()) mismatch(what, "a number", j);
  return j.get<double>();
}
const std::string& json_string(const Json& j, std::string_view what) {
  if (!j.is_string()) mismatch(what, "a string", j);
  return j.get_ref<const std::string&>();
}
const Json& json_array(const Json& j, std::string_view what) {
  if (!j.is_array()) mismatch(what, "an array", j);
  return j;
}
const Json& json_object(const Json& j, std::string_view what) {
  if (!j.is_object()) mismatch(what, "an object", j);
  return j;
}

const Json* json_find(const Json& j, std::string_view key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

Json json_numbers(const std::vector<double>& xs) {
  Json a = Json::array();
  for (double x : xs) a.push_back(x);  // nlohmann writes non-finite doubles as null
  return a;
}

namespace {

// Integral doubles are written as integers ("293", not "293.0"), as the project's files always
// had them: readers (the report's Python, people) see a temperature or a count as a whole number.
void integral_doubles_as_integers(Json& j) {
  if (j.is_number_float()) {
    const double x = j.get<double>();
    if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 1e15) j = static_cast<std::int64_t>(x);
  } else if (j.is_structured()) {
    for (auto& e : j) integral_doubles_as_integers(e);
  }
}

// Arrays holding only numbers and nulls on one line: a curve of 400 points would otherwise take
// 400 lines (nlohmann writes one element per line).
std::string flat_number_arrays(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '"') {  // a string is copied as it is, brackets and all
      std::size_t e = i + 1;
      while (e < text.size() && text[e] != '"') e += text[e] == '\\' ? 2 : 1;
      out.append(text, i, e + 1 - i);
      i = e + 1;
      continue;
    }
    if (text[i] != '[') {
      out += text[i++];
      continue;
    }
    std::size_t k = i + 1;
    bool numeric = true, any = false;
    for (; k < text.size() && text[k] != ']'; ++k) {
      const char c = text[k];
      if (c == '[' || c == '{' || c == '"') {
        numeric = false;
        break;
      }
      any = any || !std::isspace(static_cast<unsigned char>(c));
    }
    if (!numeric || k >= text.size() || !any) {
      out += text[i++];
      continue;
    }
    // "[\n  1,\n  2\n]" -> "[1, 2]"
    out += '[';
    std::string item;
    bool first = true;
    for (std::size_t m = i + 1; m <= k; ++m) {
      const char c = m < k ? text[m] : ',';
      if (c == ',') {
        if (!first) out += ", ";
        out += item;
        item.clear();
        first = false;
      } else if (!std::isspace(static_cast<unsigned char>(c))) {
        item += c;
      }
    }
    out += ']';
    i = k + 1;
  }
  return out;
}

}  // namespace

std::string json_dump(const Json& j) {
  Json copy = j;
  integral_doubles_as_integers(copy);
  return flat_number_arrays(copy.dump(2, ' ', false, Json::error_handler_t::replace));
}

Json json_parse(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const Json::out_of_range& e) {  // e.g. a number beyond a double (1e400)
    throw InputError(fmt::format("{}: invalid JSON: {}", source, e.what()));
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character
    int line = 1, col = 1;
    for (std::size_t k = 0; k + 1 < e.byte && k < text.size(); ++k) {
      if (text[k] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string msg = e.what();
    if (auto p = msg.find("syntax error"); p != std::string::npos) msg = msg.substr(p);  // drop the library's prefix
    throw InputError(fmt::format("{}:{}:{}: invalid JSON: {}", source, line, col, msg));
  }
}

Json json_read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open '{}'", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return json_parse(ss.str(), path);
}

void json_write_file(const std::string& path, const Json& j) { write_text_atomically(path, json_dump(j) + "\n"); }

}  // namespace pbx
