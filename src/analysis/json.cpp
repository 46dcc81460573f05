#include "analysis/json.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"

namespace pbx {

namespace {

const char* type_name(const Json& j) {
  if (j.is_null()) return "null";
  if (j.is_bool()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  return "an object";
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& source) : s_(text), src_(source) {}

  Json document() {
    Json v = value();
    ws();
    if (i_ != s_.size()) fail("unexpected text after the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& msg) const {
    int line = 1, col = 1;
    for (std::size_t k = 0; k < i_ && k < s_.size(); ++k) {
      if (s_[k] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw InputError(fmt::format("{}:{}:{}: invalid JSON: {}", src_, line, col, msg));
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  bool literal(const char* word) {
    std::size_t n = std::char_traits<char>::length(word);
    if (s_.compare(i_, n, word) == 0) {
      i_ += n;
      return true;
    }
    return false;
  }
  Json value() {
    ws();
    if (i_ >= s_.size()) fail("unexpected end of input");
    char c = s_[i_];
    if (c == '{') return object();
    if (c == '[') return array();
    if (c == '"') return Json(string());
    if (literal("true")) return Json(true);
    if (literal("false")) return Json(false);
    if (literal("null")) return Json();
    // NaN/Infinity are not JSON, but Python's json module writes them; accept them on reading.
    if (literal("NaN")) return Json(std::nan(""));
    if (literal("Infinity")) return Json(HUGE_VAL);
    if (literal("-Infinity")) return Json(-HUGE_VAL);
    return number();
  }
  Json number() {
    const char* begin = s_.c_str() + i_;
    char* end = nullptr;
    double x = std::strtod(begin, &end);
    if (end == begin) fail("expected a value");
    i_ += static_cast<std::size_t>(end - begin);
    return Json(x);
  }
  std::string string() {
    ++i_;  // opening quote
    std::string out;
    while (true) {
      if (i_ >= s_.size()) fail("unterminated string");
      char c = s_[i_++];
      if (c == '"') return out;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) fail("unterminated string");
      char e = s_[i_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': out += utf8(hex4()); break;
        default: fail("bad escape in string");
      }
    }
  }
  unsigned hex4() {
    if (i_ + 4 > s_.size()) fail("bad \\u escape");
    unsigned cp = 0;
    for (int k = 0; k < 4; ++k) {
      char h = s_[i_++];
      cp <<= 4;
      if (h >= '0' && h <= '9') cp |= unsigned(h - '0');
      else if (h >= 'a' && h <= 'f') cp |= unsigned(h - 'a' + 10);
      else if (h >= 'A' && h <= 'F') cp |= unsigned(h - 'A' + 10);
      else fail("bad \\u escape");
    }
    if (cp >= 0xD800 && cp < 0xDC00 && s_.compare(i_, 2, "\\u") == 0) {  // surrogate pair
      i_ += 2;
      unsigned lo = hex4();
      cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
    }
    return cp;
  }
  static std::string utf8(unsigned cp) {
    std::string o;
    if (cp < 0x80) {
      o += char(cp);
    } else if (cp < 0x800) {
      o += char(0xC0 | (cp >> 6));
      o += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      o += char(0xE0 | (cp >> 12));
      o += char(0x80 | ((cp >> 6) & 0x3F));
      o += char(0x80 | (cp & 0x3F));
    } else {
      o += char(0xF0 | (cp >> 18));
      o += char(0x80 | ((cp >> 12) & 0x3F));
      o += char(0x80 | ((cp >> 6) & 0x3F));
      o += char(0x80 | (cp & 0x3F));
    }
    return o;
  }
  Json array() {
    ++i_;
    Json::Array a;
    ws();
    if (i_ < s_.size() && s_[i_] == ']') {
      ++i_;
      return Json(std::move(a));
    }
    while (true) {
      a.push_back(value());
      ws();
      if (i_ < s_.size() && s_[i_] == ',') {
        ++i_;
      } else if (i_ < s_.size() && s_[i_] == ']') {
        ++i_;
        return Json(std::move(a));
      } else {
        fail("expected ',' or ']' in array");
      }
    }
  }
  Json object() {
    ++i_;
    Json o = Json::object();
    ws();
    if (i_ < s_.size() && s_[i_] == '}') {
      ++i_;
      return o;
    }
    while (true) {
      ws();
      if (i_ >= s_.size() || s_[i_] != '"') fail("expected a key string in object");
      std::string key = string();
      ws();
      if (i_ >= s_.size() || s_[i_] != ':') fail("expected ':' after key");
      ++i_;
      o.set(key, value());
      ws();
      if (i_ < s_.size() && s_[i_] == ',') {
        ++i_;
      } else if (i_ < s_.size() && s_[i_] == '}') {
        ++i_;
        return o;
      } else {
        fail("expected ',' or '}' in object");
      }
    }
  }

  const std::string& s_;
  const std::string& src_;
  std::size_t i_ = 0;
};

void escape_to(std::string& out, const std::string& s) {
  out += '"';
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

}  // namespace

Json Json::numbers(const std::vector<double>& xs) {
  Array a;
  a.reserve(xs.size());
  for (double x : xs) a.emplace_back(x);  // non-finite values are written as null by dump()
  return Json(std::move(a));
}

bool Json::as_bool(const std::string& what) const {
  if (!is_bool()) throw InputError(fmt::format("{}: expected a boolean, found {}", what, type_name(*this)));
  return std::get<bool>(v_);
}
double Json::as_number(const std::string& what) const {
  if (!is_number()) throw InputError(fmt::format("{}: expected a number, found {}", what, type_name(*this)));
  return std::get<double>(v_);
}
const std::string& Json::as_string(const std::string& what) const {
  if (!is_string()) throw InputError(fmt::format("{}: expected a string, found {}", what, type_name(*this)));
  return std::get<std::string>(v_);
}
const Json::Array& Json::as_array(const std::string& what) const {
  if (!is_array()) throw InputError(fmt::format("{}: expected an array, found {}", what, type_name(*this)));
  return std::get<Array>(v_);
}
const Json::Object& Json::as_object(const std::string& what) const {
  if (!is_object()) throw InputError(fmt::format("{}: expected an object, found {}", what, type_name(*this)));
  return std::get<Object>(v_);
}
Json::Array& Json::array_ref() {
  if (!is_array()) v_ = Array{};
  return std::get<Array>(v_);
}

const Json* Json::find(const std::string& key) const {
  if (!is_object()) return nullptr;
  for (const auto& [k, v] : std::get<Object>(v_)) {
    if (k == key) return &v;
  }
  return nullptr;
}

Json& Json::set(const std::string& key, Json value) {
  if (!is_object()) v_ = Object{};
  auto& o = std::get<Object>(v_);
  for (auto& [k, v] : o) {
    if (k == key) {
      v = std::move(value);
      return v;
    }
  }
  o.emplace_back(key, std::move(value));
  return o.back().second;
}

void Json::push(Json value) { array_ref().push_back(std::move(value)); }

void Json::dump_to(std::string& out, int indent, int level) const {
  std::string pad, pad_end;
  if (indent > 0) {
    pad.assign(1, '\n');
    pad.append(std::size_t(indent * (level + 1)), ' ');
    pad_end.assign(1, '\n');
    pad_end.append(std::size_t(indent * level), ' ');
  }
  if (is_null()) {
    out += "null";
  } else if (is_bool()) {
    out += std::get<bool>(v_) ? "true" : "false";
  } else if (is_number()) {
    double x = std::get<double>(v_);
    if (!std::isfinite(x)) {
      out += "null";  // JSON has no NaN; readers get null for "not available"
    } else if (x == std::floor(x) && std::fabs(x) < 1e15) {
      out += fmt::format("{:.0f}", x);
    } else {
      out += fmt::format("{}", x);  // shortest representation that round-trips
    }
  } else if (is_string()) {
    escape_to(out, std::get<std::string>(v_));
  } else if (is_array()) {
    const auto& a = std::get<Array>(v_);
    if (a.empty()) {
      out += "[]";
      return;
    }
    // Arrays of numbers stay on one line: curves would otherwise take a line per point.
    bool flat = true;
    for (const auto& e : a) flat = flat && (e.is_number() || e.is_null());
    out += '[';
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (k) out += flat ? ", " : ",";
      if (!flat) out += pad;
      a[k].dump_to(out, indent, level + 1);
    }
    if (!flat) out += pad_end;
    out += ']';
  } else {
    const auto& o = std::get<Object>(v_);
    if (o.empty()) {
      out += "{}";
      return;
    }
    out += '{';
    for (std::size_t k = 0; k < o.size(); ++k) {
      if (k) out += ',';
      out += pad;
      escape_to(out, o[k].first);
      out += indent > 0 ? ": " : ":";
      o[k].second.dump_to(out, indent, level + 1);
    }
    out += pad_end;
    out += '}';
  }
}

std::string Json::dump(int indent) const {
  std::string out;
  dump_to(out, indent, 0);
  return out;
}

Json Json::parse(const std::string& text, const std::string& source) { return Parser(text, source).document(); }

Json Json::read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open '{}'", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

void Json::write_file(const std::string& path) const {
  // written whole or not at all: analysis.json is a result file
  write_text_atomically(path, dump() + "\n");
}

}  // namespace pbx
