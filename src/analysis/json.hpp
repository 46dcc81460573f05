#pragma once
// A small JSON document model for the analysis files (run.json, study.json, analysis.json,
// fits.json). The project's dependency set has no C++ JSON library; these files are small and
// flat, so a reader/writer of plain RFC 8259 JSON is all that is needed.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace pbx {

class Json {
 public:
  using Array = std::vector<Json>;
  // Keys keep insertion order so that written files read in a meaningful order.
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() = default;  // null
  Json(std::nullptr_t) {}
  Json(bool b) : v_(b) {}
  Json(double x) : v_(x) {}
  Json(int x) : v_(static_cast<double>(x)) {}
  Json(long x) : v_(static_cast<double>(x)) {}
  Json(std::size_t x) : v_(static_cast<double>(x)) {}
  Json(const char* s) : v_(std::string(s)) {}
  Json(std::string s) : v_(std::move(s)) {}
  Json(Array a) : v_(std::move(a)) {}
  Json(Object o) : v_(std::move(o)) {}
  static Json object() { return Json(Object{}); }
  static Json array() { return Json(Array{}); }
  // A double array; non-finite entries are written as null.
  static Json numbers(const std::vector<double>& xs);

  bool is_null() const { return std::holds_alternative<std::monostate>(v_); }
  bool is_bool() const { return std::holds_alternative<bool>(v_); }
  bool is_number() const { return std::holds_alternative<double>(v_); }
  bool is_string() const { return std::holds_alternative<std::string>(v_); }
  bool is_array() const { return std::holds_alternative<Array>(v_); }
  bool is_object() const { return std::holds_alternative<Object>(v_); }

  // Typed access; `what` names the value in the InputError thrown on a type mismatch.
  bool as_bool(const std::string& what = "value") const;
  double as_number(const std::string& what = "value") const;
  const std::string& as_string(const std::string& what = "value") const;
  const Array& as_array(const std::string& what = "value") const;
  const Object& as_object(const std::string& what = "value") const;
  Array& array_ref();

  // Object access. find() returns nullptr when absent; set() replaces or appends.
  const Json* find(const std::string& key) const;
  Json& set(const std::string& key, Json value);
  void push(Json value);  // array append

  // Serialises with two-space indentation; numbers with 17 significant digits when needed.
  std::string dump(int indent = 2) const;
  static Json parse(const std::string& text, const std::string& source = "<json>");
  static Json read_file(const std::string& path);
  void write_file(const std::string& path) const;

 private:
  void dump_to(std::string& out, int indent, int level) const;
  std::variant<std::monostate, bool, double, std::string, Array, Object> v_;
};

}  // namespace pbx
