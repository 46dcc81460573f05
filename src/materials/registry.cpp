// The material registry: the built-in models (linear_elastic, and every deviator x EOS pair of
// models.hpp's lists) and the models registered at run time by register_material().
#include <map>
#include <mutex>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "core/param_table.hpp"
#include "materials/material.hpp"
#include "materials/models.hpp"

namespace pbx {

namespace {

template <int D>
using Registry = std::map<std::string, MaterialFactory<D>>;

template <int D, class Dev, class... Eos>
void add_deviator(Registry<D>& r, TypeList<Eos...>) {
  (r.emplace(Solid<D, Dev, Eos>::model_name(), make_solid<D, Dev, Eos>), ...);
}

template <int D, class... Dev>
void add_compositions(Registry<D>& r, TypeList<Dev...>) {
  (add_deviator<D, Dev>(r, EquationsOfState{}), ...);
}

template <int D>
Registry<D> built_in() {
  Registry<D> r = {{"linear_elastic", make_linear_elastic<D>}};
  add_compositions<D>(r, Deviators{});
  return r;
}

// Built-in models and those added by register_material(), behind one lock: registration normally
// happens before any run, but nothing forbids a program from registering from a thread.
template <int D>
struct Models {
  std::mutex lock;
  Registry<D> map = built_in<D>();
};

template <int D>
Models<D>& models() {
  static Models<D> m;
  return m;
}

}  // namespace

template <int D>
void register_material(const std::string& name, MaterialFactory<D> factory) {
  if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
    throw InputError(fmt::format("register_material: '{}': a model name is lower-case letters, digits and '_'", name));
  if (!factory) throw InputError(fmt::format("register_material: '{}': no factory given", name));
  auto& m = models<D>();
  std::lock_guard<std::mutex> hold(m.lock);
  if (!m.map.emplace(name, std::move(factory)).second)
    throw InputError(fmt::format("register_material: a model named '{}' is already registered", name));
}

std::vector<std::string> material_models() {
  std::set<std::string> names;
  for (int pass = 0; pass < 2; ++pass) {
    auto collect = [&](auto& m) {
      std::lock_guard<std::mutex> hold(m.lock);
      for (auto& [k, v] : m.map) names.insert(k);
    };
    pass == 0 ? collect(models<2>()) : collect(models<3>());
  }
  return {names.begin(), names.end()};
}

template <int D>
std::unique_ptr<Material<D>> make_material(const ParamTable& t, const MaterialContext& ctx) {
  const std::string model = t.string("model");
  MaterialFactory<D> factory;
  std::vector<std::string> known;  // this dimension's models: one registered for 3-D only is not offered in 2-D
  {
    auto& m = models<D>();
    std::lock_guard<std::mutex> hold(m.lock);
    if (auto it = m.map.find(model); it != m.map.end()) factory = it->second;
    for (auto& [k, v] : m.map) known.push_back(k);
  }
  if (!factory)
    t.fail("model",
           fmt::format("unknown material model '{}' (known for {}-D decks: {})", model, D, fmt::join(known, ", ")));
  return factory(t, ctx);
}

template void register_material<2>(const std::string&, MaterialFactory<2>);
template void register_material<3>(const std::string&, MaterialFactory<3>);
template std::unique_ptr<Material<2>> make_material<2>(const ParamTable&, const MaterialContext&);
template std::unique_ptr<Material<3>> make_material<3>(const ParamTable&, const MaterialContext&);

}  // namespace pbx
