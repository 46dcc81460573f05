#pragma once
// Contact laws registered at run time, by name: a law written like the built-in ones (a struct with
// `needs_normal` and `exchange(const NodeContact<D>&)` for D = 2 and 3, contact/law_coulomb.hpp is
// the model) becomes a law a deck can name in [contact] or [[contact.pair]] with one call,
//   register_contact_law<MyLaw>("my_law", [](const ParamTable& t) { return MyLaw{t.number("k")}; });
// The function reads the law's own keys from the deck table (the table's unknown keys are still
// refused). Built-in laws are dispatched by a switch (contact/field_contact.cpp); a registered one
// costs one virtual call per exchange. docs/extending.md "A contact law".
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/node_contact.hpp"

namespace pbx {

class ParamTable;

class ContactLawPlugin {
 public:
  virtual ~ContactLawPlugin() = default;
  virtual bool needs_normal() const = 0;
  virtual Exchange<2> exchange(const NodeContact<2>& c) const = 0;
  virtual Exchange<3> exchange(const NodeContact<3>& c) const = 0;
};

using ContactLawReader = std::function<std::shared_ptr<const ContactLawPlugin>(const ParamTable&)>;

// Registers a reader under `name`; throws std::invalid_argument for a name that is taken (a
// built-in law's or a registered one's) or not a lower-case identifier.
void register_contact_law_reader(const std::string& name, ContactLawReader read);
// The reader registered under name, or nullptr.
const ContactLawReader* find_contact_law(const std::string& name);
// The registered names, sorted (for error messages).
std::vector<std::string> registered_contact_laws();

namespace detail {
template <class Law>
class PluginOf final : public ContactLawPlugin {
 public:
  explicit PluginOf(Law law) : law_(std::move(law)) {}
  bool needs_normal() const override { return Law::needs_normal; }
  Exchange<2> exchange(const NodeContact<2>& c) const override { return law_.exchange(c); }
  Exchange<3> exchange(const NodeContact<3>& c) const override { return law_.exchange(c); }

 private:
  Law law_;
};
}  // namespace detail

template <class Law, class Read>
void register_contact_law(const std::string& name, Read read) {
  register_contact_law_reader(name, [read](const ParamTable& t) -> std::shared_ptr<const ContactLawPlugin> {
    return std::make_shared<detail::PluginOf<Law>>(read(t));
  });
}

}  // namespace pbx
