#include "contact/law_registry.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <stdexcept>

namespace pbx {

namespace {
std::map<std::string, ContactLawReader>& registry() {
  static std::map<std::string, ContactLawReader> r;
  return r;
}
std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}
bool identifier(const std::string& s) {
  if (s.empty() || !(s[0] >= 'a' && s[0] <= 'z')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; });
}
}  // namespace

void register_contact_law_reader(const std::string& name, ContactLawReader read) {
  static const char* const builtin[] = {"weld", "frictionless", "coulomb", "adhesion", "binder_layer"};
  if (!identifier(name)) throw std::invalid_argument("contact law name '" + name + "' is not a lower-case identifier");
  if (std::find(std::begin(builtin), std::end(builtin), name) != std::end(builtin))
    throw std::invalid_argument("contact law name '" + name + "' is a built-in law's");
  std::lock_guard<std::mutex> lock(registry_mutex());
  if (!registry().emplace(name, std::move(read)).second)
    throw std::invalid_argument("contact law name '" + name + "' is already registered");
}

const ContactLawReader* find_contact_law(const std::string& name) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  const auto it = registry().find(name);
  return it == registry().end() ? nullptr : &it->second;
}

std::vector<std::string> registered_contact_laws() {
  std::lock_guard<std::mutex> lock(registry_mutex());
  std::vector<std::string> names;
  for (const auto& [name, read] : registry()) names.push_back(name);
  return names;
}

}  // namespace pbx
