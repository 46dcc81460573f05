// A structure-aware deck fuzzer with a fixed budget and seed: the example run decks are parsed with
// toml++, one leaf (or table) is mutated, and the deck is built as `pbxmpm check` builds it. Every
// outcome must be a built scene or an InputError (a clear message naming the key); any other
// exception, a crash or a sanitizer report fails the test. Mutations that make a deck certainly
// invalid (an unknown key, a unit of the wrong dimension, a word where a number is read, a
// non-finite number) must be refused: never a silent success.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "scene_fixture.hpp"
#include "setup/build_scene.hpp"

namespace fs = std::filesystem;
using namespace pbx;

namespace {

// Every value node of the table, with the node that holds it (a table or an array) and its key or
// index: what a mutation may replace or remove.
struct Leaf {
  toml::node* parent;
  std::string key;    // for a table parent
  std::size_t index;  // for an array parent
  std::string path;
};

void collect(toml::node& n, const std::string& path, std::vector<Leaf>& out) {
  if (auto* t = n.as_table()) {
    for (auto& [k, v] : *t) {
      const std::string p = path.empty() ? std::string(k.str()) : path + "." + std::string(k.str());
      out.push_back({t, std::string(k.str()), 0, p});
      collect(v, p, out);
    }
  } else if (auto* a = n.as_array()) {
    for (std::size_t i = 0; i < a->size(); ++i) {
      const std::string p = fmt::format("{}[{}]", path, i);
      out.push_back({a, "", i, p});
      collect(*a->get(i), p, out);
    }
  }
}

toml::node* node_of(const Leaf& l) {
  if (auto* t = l.parent->as_table()) return t->get(l.key);
  return l.parent->as_array()->get(l.index);
}

void replace(const Leaf& l, toml::node&& v) {
  if (auto* t = l.parent->as_table()) {
    t->insert_or_assign(l.key, std::move(v));
  } else {
    auto* a = l.parent->as_array();
    a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(l.index), std::move(v));
  }
}

// A string holding a quantity ("20 um", "0.3 m/s"): its unit can be swapped for one of another
// dimension, which no key accepts.
bool is_quantity(const std::string& s) {
  return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '-') &&
         s.find(' ') != std::string::npos;
}

enum class Expect { refused, either };

}  // namespace

TEST(DeckFuzz, MutatedExampleDecksAreBuiltOrRefusedClearly) {
  const fs::path ex(PBXMPM_EXAMPLES_DIR);
  struct Source {
    std::string name, text;
    double weight;
  };
  const std::vector<Source> sources = {
      {"demo/elastic_block_die.toml", test::slurp(ex / "demo" / "elastic_block_die.toml"), 0.45},
      {"contact/two_disks.toml", test::slurp(ex / "contact" / "two_disks.toml"), 0.45},
      {"paper/base.toml", test::slurp(ex / "paper" / "base.toml"), 0.10},
  };
  std::mt19937_64 rng(20261204);
  std::discrete_distribution<int> pick_source({sources[0].weight, sources[1].weight, sources[2].weight});
  const auto start = std::chrono::steady_clock::now();
  const int budget = 1500;  // mutations; also stopped after 90 s on a slow (sanitized) build
  int built = 0, refused = 0, tried = 0;
  for (int k = 0; k < budget; ++k) {
    if (std::chrono::steady_clock::now() - start > std::chrono::seconds(90)) break;
    const Source& src = sources[static_cast<std::size_t>(pick_source(rng))];
    toml::table deck = toml::parse(src.text, src.name);
    std::vector<Leaf> leaves;
    collect(deck, "", leaves);
    ASSERT_FALSE(leaves.empty());
    const Leaf leaf = leaves[std::uniform_int_distribution<std::size_t>(0, leaves.size() - 1)(rng)];
    toml::node* node = node_of(leaf);
    Expect expect = Expect::either;
    std::string what;
    const int kind = std::uniform_int_distribution<int>(0, 6)(rng);
    if (kind == 0 && leaf.parent->is_table()) {  // an unknown key beside the real one
      leaf.parent->as_table()->insert_or_assign(leaf.key + "_typo", toml::value<int64_t>(1));
      expect = Expect::refused;
      what = "unknown key " + leaf.path + "_typo";
    } else if (kind == 1 && node->is_string() && is_quantity(*node->value<std::string>())) {
      const std::string s = *node->value<std::string>();
      const bool is_temperature = s.find(" K") != std::string::npos && s.find('/') == std::string::npos;
      replace(leaf, toml::value<std::string>(s.substr(0, s.find(' ')) + (is_temperature ? " m/s" : " K")));
      expect = Expect::refused;
      what = "wrong unit at " + leaf.path;
    } else if (kind == 2 && (node->is_number() || (node->is_string() && is_quantity(*node->value<std::string>())))) {
      replace(leaf, toml::value<std::string>("abc"));
      expect = Expect::refused;
      what = "a word for the number at " + leaf.path;
    } else if (kind == 3 && node->is_floating_point()) {
      const double bad[] = {std::nan(""), INFINITY, -INFINITY};
      replace(leaf, toml::value<double>(bad[std::uniform_int_distribution<int>(0, 2)(rng)]));
      expect = Expect::refused;
      what = "non-finite number at " + leaf.path;
    } else if (kind == 4 && (node->is_number())) {  // extreme or signed values: valid or refused
      const double f[] = {-1.0, 0.0, 1e300, 1e-300, 0.5, 2.0};
      const double x = node->is_integer() ? static_cast<double>(*node->value<int64_t>()) : *node->value<double>();
      const double v = x * f[std::uniform_int_distribution<int>(0, 5)(rng)];
      if (node->is_integer() && std::abs(v) < 1e15)
        replace(leaf, toml::value<int64_t>(static_cast<int64_t>(v)));
      else
        replace(leaf, toml::value<double>(v));
      what = "scaled number at " + leaf.path;
    } else if (kind == 5 && leaf.parent->is_table()) {  // a key removed: a default, or refused
      leaf.parent->as_table()->erase(leaf.key);
      what = "removed " + leaf.path;
    } else if (kind == 6) {  // another type in its place
      if (node->is_table() || node->is_array())
        replace(leaf, toml::value<int64_t>(3));
      else
        replace(leaf, toml::table{{"x", 1}});
      what = "another type at " + leaf.path;
    } else {
      continue;
    }
    ++tried;
    std::ostringstream text;
    text << deck;
    bool ok = false;
    std::string error;
    try {
      Deck d = Deck::from_string(text.str(), src.name);
      Scene<2> sc = build_scene<2>(d);
      d.check_unused();
      ok = true;
    } catch (const InputError& e) {
      error = e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << src.name << ", " << what << ": not a clear input error but " << typeid(e).name() << ": "
                    << e.what() << "\n"
                    << text.str();
      continue;
    }
    if (ok) {
      ++built;
      EXPECT_NE(expect, Expect::refused) << src.name << ", " << what << ": an invalid deck was accepted\n"
                                         << text.str();
    } else {
      ++refused;
      EXPECT_FALSE(error.empty()) << src.name << ", " << what;
    }
  }
  std::printf("deck fuzz: %d mutations, %d built, %d refused\n", tried, built, refused);
  EXPECT_GT(tried, 50);
}
