// pbxmpm pack DECK [--out DIR] [--from-image FILE.png]: builds a mesostructure from the deck's
// [packing] table (or imports a segmented image) and writes packing.csv/.json/.png.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "io/deck.hpp"
#include "microstructure/image_import.hpp"
#include "microstructure/packing.hpp"

namespace pbx::app {

namespace {

struct PackOptions {
  std::string deck;
  std::string out = "packing";
  std::string image;
};

void run_pack(const PackOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const Deck deck = Deck::from_file(o.deck);
  const DeckTable t = deck.root().table("packing");
  // Only [packing] is read (and checked), so a run deck packs its specimen as the run would. The
  // output folder is made once the deck is valid and before the packing is computed, so an
  // unwritable --out fails at once.
  Packing p;
  if (!o.image.empty() || t.has("image")) {
    ImageSpec spec = read_image_spec(t, o.image);
    if (o.image.empty()) spec.file = deck.resolve(spec.file);
    t.check_unused();
    std::filesystem::create_directories(o.out);
    p = import_image(spec);
  } else {
    PackingSpec spec = read_packing_spec(t);
    t.check_unused();
    if (auto specimen = deck.root().optional_table("specimen"); specimen && specimen->has("seed")) {
      const long seed = specimen->integer("seed");  // a run deck's specimen.seed wins over packing.seed
      if (seed < 0) specimen->fail("seed", fmt::format("must be >= 0 (got {})", seed));
      spec.seed = static_cast<std::uint64_t>(seed);
    }
    std::filesystem::create_directories(o.out);
    std::printf("pack: target porosity %.4f (density %.4f g/cm3, TMD %.4f g/cm3), seed %llu\n", spec.porosity,
                (1 - spec.porosity) * spec.tmd() / 1000, spec.tmd() / 1000, static_cast<unsigned long long>(spec.seed));
    p = generate_packing(spec);
  }
  write_packing(p, o.out);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PackingStats& s = p.stats;
  std::printf("pack: %zu grains (%d coarse, %d fine), porosity %.5f, density %.4f g/cm3, TMD %.4f g/cm3\n",
              p.grains.size(), s.grains_coarse, s.grains_fine, s.porosity, s.density / 1000, s.tmd / 1000);
  std::printf("pack: TATB:binder mass %.4f:%.4f, area fractions TATB %.4f binder %.4f\n", 100 * s.tatb_mass_fraction,
              100 * (1 - s.tatb_mass_fraction), s.tatb_area_fraction, s.binder_area_fraction);
  if (p.tiles[0] * p.tiles[1] > 1)
    std::printf("pack: %d x %d copies of the packed %.4g x %.4g m cell (packing.tiles)\n", p.tiles[0], p.tiles[1],
                p.box.x() / p.tiles[0], p.box.y() / p.tiles[1]);
  std::printf("pack: coat %.3f-%.3f um, %d contact colours, %.2f s -> %s/packing.{csv,json,png}\n", s.coat_min * 1e6,
              s.coat_max * 1e6, s.colours, secs, o.out.c_str());
}

}  // namespace

void register_pack(CLI::App& app) {
  auto o = std::make_shared<PackOptions>();
  auto* cmd = app.add_subcommand("pack", "Generate a mesostructure (coated TATB grains) or import a segmented image");
  cmd->add_option("deck", o->deck, "Deck with a [packing] table")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out, "Output folder (packing.csv, packing.json, packing.png)");
  cmd->add_option("--from-image", o->image,
                  "Segmented PNG image; the deck's [packing] table gives pixel_size and "
                  "the [packing.legend] colours")
      ->check(CLI::ExistingFile);
  cmd->callback([o] { run_pack(*o); });
}

}  // namespace pbx::app
