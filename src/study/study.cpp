#include "study/study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <omp.h>
#include <toml++/toml.h>
#include <unistd.h>

#ifdef PBXMPM_HAVE_MPI
#include <mpi.h>
#endif

#include "setup/build_scene.hpp"
#include "analysis/run_analysis.hpp"
#include "analysis/study_report.hpp"
#include "core/error.hpp"
#include "io/atomic_write.hpp"
#include "io/deck_override.hpp"
#include "io/checkpoint.hpp"
#include "io/output_lock.hpp"
#include "io/deck.hpp"
#include "io/json.hpp"
#include "run/runner.hpp"
#include "study/run_phases.hpp"
#include "study/study_status.hpp"

namespace pbx {

namespace fs = std::filesystem;

bool is_folder_name(const std::string& name) {
  bool ok = !name.empty() && name.front() != '.' && name.front() != '-';
  for (char c : name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  return ok;
}

namespace {

// The line before the study's [analysis] table in a generated run deck (run_deck_text, deck_body).
constexpr const char* analysis_marker =
    "# how this run is analysed: the study's [analysis] table (pbxmpm analyze reads it from run.json)";

std::string node_text(const toml::node& n) {
  std::stringstream ss;
  if (auto* s = n.as_string()) {
    ss << toml::value<std::string>(s->get());
    return ss.str();
  }
  if (auto* f = n.as_floating_point()) return fmt::format("{}", f->get());  // shortest round-trip form
  n.visit([&](auto&& v) { ss << v; });
  return ss.str();
}

std::string label_of(const std::string& value_text) {
  std::string out;
  for (char c : value_text)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') out += c;
  return out.empty() ? "v" : out;
}

// A group name becomes part of its runs' folder names (runs/<group>-<value>-s<seed>): a '/' or
// '..' would put runs in nested folders or outside runs/.
void check_folder_name(const DeckTable& t, const std::string& key, const std::string& name) {
  if (!is_folder_name(name))
    t.fail(key, fmt::format("'{}' names a folder: use letters, digits, '_', '-' and '.' (not first)", name));
}

bool is_seed_key(const std::string& k) { return k == "specimen.seed" || k == "packing.seed"; }

}  // namespace

int launched_ranks() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(var)) return std::max(1, std::atoi(v));
  return 0;
}

namespace {

struct Mpi {
  int rank = 0, size = 1;
  bool owns = false;
  Mpi() {
#ifdef PBXMPM_HAVE_MPI
    int init = 0;
    MPI_Initialized(&init);
    // Only join MPI when launched by mpirun (a plain run needs no MPI runtime at all).
    if (!init && launched_ranks() > 0) {
      MPI_Init(nullptr, nullptr);
      owns = true;
      init = 1;
    }
    if (init) {
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
#endif
  }
  void barrier() const {
#ifdef PBXMPM_HAVE_MPI
    if (size > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
  }
  void broadcast(std::vector<char>& v) const {  // rank 0's contents to every rank (same size everywhere)
#ifdef PBXMPM_HAVE_MPI
    if (size > 1) MPI_Bcast(v.data(), static_cast<int>(v.size()), MPI_CHAR, 0, MPI_COMM_WORLD);
#else
    (void)v;
#endif
  }
  int sum(int v) const {
#ifdef PBXMPM_HAVE_MPI
    if (size > 1) {
      int out = 0;
      MPI_Allreduce(&v, &out, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
      return out;
    }
#endif
    return v;
  }
  ~Mpi() {
#ifdef PBXMPM_HAVE_MPI
    if (owns) MPI_Finalize();
#endif
  }
};

// Simulated to the end (run.json says so). Not also "analysed": a finished run whose analysis
// failed or is missing is re-analysed with the finished runs, never simulated again (hours at
// 2.5 um cells); the report names a run whose analysis.json is still missing.
// A deck whose [specimen] is packed from a seed (not read from specimen.packing_dir).
bool seeds_its_specimen(const toml::table& deck) {
  const toml::table* spec = deck["specimen"].as_table();
  return spec && !spec->contains("packing_dir");
}

// Builds a run deck's scene in the deck's dimension (2-D plane strain, or 3-D: the die with a depth,
// a packed specimen extruded through it) and hands it to f.
template <class F>
void with_study_scene(const Deck& deck, SceneNotes notes, F&& f) {
  const int dim = deck_dimension(deck);
  if (dim == 2) {
    Scene<2> scene = build_scene<2>(deck, notes);
    f(scene);
  } else if (dim == 3) {
    Scene<3> scene = build_scene<3>(deck, notes);
    f(scene);
  } else {
    throw InputError(fmt::format("{}: run.dimension = {}: must be 2 or 3", deck.name(), dim));
  }
}

bool finished(const fs::path& dir) {
  if (!fs::exists(dir / "run.json")) return false;
  try {
    const Json run = json_read_file((dir / "run.json").string());
    const Json* st = json_find(run, "status");
    return st && st->is_string() && *st == "finished";
  } catch (const InputError&) {
    return false;  // unreadable: not a finished run, it is run again
  }
}

// The first line of a run's deck names the base deck's path, which may move with the study; the
// study's [analysis] table after analysis_marker says how the run is read, not what it computes.
std::string deck_body(const std::string& text) {
  const auto nl = text.find('\n');
  if (nl == std::string::npos) return std::string();
  std::string body = text.substr(nl + 1);
  if (const auto m = body.find(std::string("\n") + analysis_marker); m != std::string::npos) body.resize(m);
  return body;
}

// First line where a finished run's deck and the one the study gives now differ ("" if equal).
std::string first_difference(const std::string& was, const std::string& now) {
  std::istringstream a(deck_body(was)), b(deck_body(now));
  std::string la, lb;
  for (int line = 2;; ++line) {
    const bool ga = static_cast<bool>(std::getline(a, la)), gb = static_cast<bool>(std::getline(b, lb));
    if (!ga && !gb) return "";
    if (!ga || !gb || la != lb)
      return fmt::format("line {}: was '{}', now '{}'", line, ga ? la : "<end>", gb ? lb : "<end>");
  }
}

}  // namespace

StudySpec read_study(const std::string& file) {
  Deck deck = Deck::from_file(file);
  const DeckTable st = deck.root().table("study");
  StudySpec s;
  s.name = st.string("name");
  s.deck = fs::absolute(file).string();
  s.base_deck = fs::absolute(deck.resolve(st.string("base"))).string();
  {
    // a folder opens as an empty stream and the study itself parses as a deck: both failed only
    // when the first run was built ("grid: required table missing"), after the study's files were written
    std::error_code ec;
    if (fs::is_directory(s.base_deck, ec))
      st.fail("base", fmt::format("'{}' is a folder, not a run deck", s.base_deck));
    if (fs::equivalent(s.base_deck, file, ec))
      st.fail("base", "names this study deck itself; give the run deck the study varies");
    std::ifstream in(s.base_deck);
    if (!in) st.fail("base", fmt::format("cannot open base deck '{}'", s.base_deck));
    std::stringstream ss;
    ss << in.rdbuf();
    s.base_text = ss.str();
    try {
      if (toml::parse(s.base_text, s.base_deck).contains("study"))
        st.fail("base", fmt::format("'{}' is a study deck ([study]); give the run deck the study varies", s.base_deck));
    } catch (const toml::parse_error&) {
      // reported with its line when the runs are built
    }
  }
  // study.seeds for every group; a group's own `seeds` replaces them for its runs (e.g. more
  // microstructures where the specimen-to-specimen scatter matters)
  const auto read_seeds = [](const DeckTable& t, std::vector<long> def) {
    if (!t.has("seeds")) return def;
    std::vector<long> out;
    for (double v : t.quantities("seeds", dim::none)) {
      if (!(v >= 0 && v < 9.0e15) || v != std::floor(v)) t.fail("seeds", "must be non-negative integers below 9e15");
      out.push_back(static_cast<long>(v));
    }
    if (out.empty()) t.fail("seeds", "must list at least one seed");
    return out;
  };
  const std::vector<long> study_seeds = read_seeds(st, {1});
  bool several_seeds = study_seeds.size() > 1;
  // Overrides are kept as TOML text; the toml++ tree of the study deck gives them back verbatim.
  const toml::table tree = toml::parse(deck.text(), file);
  auto overrides_of = [&](const toml::table* t) {
    std::vector<std::pair<std::string, std::string>> out;
    if (!t) return out;
    for (auto&& [k, v] : *t) out.emplace_back(std::string(k.str()), node_text(v));
    return out;
  };
  // mark the [set] tables used (their keys are deck keys checked when each run is built)
  std::vector<std::pair<std::string, std::string>> common;
  if (auto set = st.optional_table("set")) {
    for (auto& k : set->keys()) set->accept(k);
  }
  common = overrides_of(tree["study"]["set"].as_table());
  const auto groups = st.tables("group");
  std::vector<std::size_t>
      own_seed_group;  // per run: its group if that group gives the seed itself, else groups.size()
  if (groups.empty()) st.fail("group", "at least one [[study.group]] is required");
  const toml::array* garr = tree["study"]["group"].as_array();
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const DeckTable& g = groups[gi];
    const std::vector<long> seeds = read_seeds(g, study_seeds);
    several_seeds = several_seeds || seeds.size() > 1;
    const std::string gname = g.string("name");
    check_folder_name(g, "name", gname);
    const std::string key = g.string("key");
    const toml::table& gt = *garr->get(gi)->as_table();
    const toml::array* values = gt["values"].as_array();
    g.accept("values");
    if (!values || values->empty()) g.fail("values", "required: an array of at least one value");
    auto gset = overrides_of(gt["set"].as_table());
    if (auto set = g.optional_table("set"))
      for (auto& k : set->keys()) set->accept(k);
    // A group whose key or overrides give the specimen's seed must keep it: the study's own seed
    // would overwrite it (and specimen.seed wins over packing.seed in a run deck), so every run
    // would share one seed. Such a group takes one study seed, and its runs record the seed used.
    const auto is_seed = is_seed_key;
    std::optional<std::string> set_seed;  // the seed text a [set] gives (group set over study set)
    for (const auto& kv : common)
      if (is_seed(kv.first)) set_seed = kv.second;
    for (const auto& kv : gset)
      if (is_seed(kv.first)) set_seed = kv.second;
    const bool own_seed = is_seed(key) || set_seed.has_value();
    if (own_seed && seeds.size() > 1) {
      if (is_seed(key))
        g.fail("key", fmt::format("this group varies '{}' itself: give study.seeds at most one seed", key));
      st.fail("seeds",
              fmt::format("group '{}' gets the specimen's seed from a [set] table: give at most one seed", gname));
    }
    for (const auto& v : *values) {
      const std::string text = node_text(v);
      for (long seed : seeds) {
        StudyRunSpec r;
        r.group = gname;
        r.key = key;
        r.value_label = text;
        r.seed = seed;
        if (own_seed) {  // the seed the run really uses
          const std::string& used = is_seed(key) ? text : *set_seed;
          // the whole text must be a non-negative integer: std::stol("2.5") is 2, a run would use
          // another seed than the one its study.json records
          std::size_t used_chars = 0;
          long v = -1;
          try {
            v = std::stol(used, &used_chars);
          } catch (const std::exception&) {
          }
          if (used_chars != used.size() || v < 0)
            g.fail(is_seed(key) ? "values" : "set", fmt::format("seed '{}' is not a non-negative integer", used));
          r.seed = v;
        }
        r.id = fmt::format("{}-{}-s{}", gname, label_of(text), r.seed);
        for (const auto& other : s.runs)
          if (other.id == r.id)
            g.fail("values", fmt::format("runs '{}' = {} and {} get the same id '{}' (the same value twice, "
                                         "or two groups of one name): every run needs its own folder",
                                         key, other.value_label, text, r.id));
        r.set = common;
        r.set.insert(r.set.end(), gset.begin(), gset.end());
        r.set.emplace_back(key, text);
        // specimen.seed decides in a run deck: it carries the study's seed, or the group's own
        r.set.emplace_back("specimen.seed", std::to_string(r.seed));
        s.runs.push_back(std::move(r));
        own_seed_group.push_back(own_seed ? gi : groups.size());
      }
    }
  }
  bool base_has_specimen = true;  // a base deck that does not parse is reported when its runs are built
  bool reads_packing = false;     // the specimen reads a packing (specimen.packing_dir): no seed applies
  try {
    const toml::table base = toml::parse(s.base_text, s.base_deck);
    base_has_specimen = base.contains("specimen");
    reads_packing = base_has_specimen && !seeds_its_specimen(base);
  } catch (const toml::parse_error&) {
  }
  const bool base_specimen = base_has_specimen, base_reads = reads_packing;
  for (std::size_t i = 0; i < s.runs.size(); ++i) {
    bool has_specimen = base_specimen, reads = base_reads;  // this run's
    for (const auto& kv : s.runs[i].set) {
      if (kv.first != "specimen.seed") has_specimen = has_specimen || kv.first.rfind("specimen.", 0) == 0;
      reads = reads || kv.first == "specimen.packing_dir";
    }
    base_has_specimen = base_has_specimen || has_specimen;
    reads_packing = reads_packing || reads;
    // a group that gives the seed itself, on a specimen no seed reaches: its runs would be one run
    // under several names (the seed is dropped from decks whose specimen is not generated)
    if (own_seed_group[i] < groups.size() && (!has_specimen || reads))
      groups[own_seed_group[i]].fail(
          is_seed_key(groups[own_seed_group[i]].string("key")) ? "key" : "set",
          fmt::format("group '{}' gives the specimen's seed, but {}: every seed would give the same run",
                      s.runs[i].group,
                      reads ? "the specimen is read from specimen.packing_dir, not generated"
                            : "the base deck has no [specimen] (no packed microstructure)"));
  }
  if (several_seeds && !base_has_specimen)
    st.fail("seeds", "the base deck has no [specimen] (no packed microstructure): every seed would give the same run");
  if (several_seeds && reads_packing)
    st.fail("seeds",
            "the specimen is read from specimen.packing_dir, not generated: every seed would give the same run");
  if (auto a = deck.root().optional_table("analysis")) {
    s.analysis = AnalysisOptions::from_deck(*a);
    std::stringstream text;
    text << toml::table{{"analysis", *tree["analysis"].as_table()}} << "\n";
    s.analysis_text = text.str();
  }
  deck.check_unused();
  return s;
}

std::string run_deck_text(const StudySpec& s, const StudyRunSpec& r) {
  toml::table base;
  try {
    base = toml::parse(s.base_text, s.base_deck);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}: {}", s.base_deck, e.source().begin.line, e.description()));
  }
  for (const auto& [key, text] : r.set) {
    // no packed specimen, or one read from a packing_dir (the last set, after every override): no seed
    if (key == "specimen.seed" && !seeds_its_specimen(base)) continue;
    apply_override(base, key, text, fmt::format("study override '{}'", key));
  }
  // The study's [analysis] table goes at the end, after its marker line, in place of any the base
  // deck has: the run is analysed by it (in the study, and by `pbxmpm analyze` when the deck is run
  // alone). Decks are compared without it (deck_body), so finished runs whose decks predate it are
  // still reused.
  if (!s.analysis_text.empty()) base.erase("analysis");
  std::stringstream ss;
  ss << fmt::format("# generated by pbxmpm study from {}\n", s.base_deck) << base << "\n";
  if (!s.analysis_text.empty()) ss << "\n" << analysis_marker << "\n" << s.analysis_text;
  return ss.str();
}

// study.json (first, so a report can name what is missing from an interrupted study) and the
// [analysis] table beside the runs (so that a later `pbxmpm report DIR` analyses them the same way;
// removed when the study deck no longer has one).
static void write_study_files(const StudySpec& s, const fs::path& out) {
  Json runs = Json::array();
  for (const auto& r : s.runs)
    runs.push_back({{"id", r.id},
                    {"dir", "runs/" + r.id},
                    {"group", r.group},
                    {"key", r.key},
                    {"value", r.value_label},
                    {"seed", r.seed}});
  json_write_file((out / "study.json").string(),
                  Json{{"name", s.name}, {"deck", s.deck}, {"base", s.base_deck}, {"runs", runs}});
  if (s.analysis_text.empty())
    fs::remove(out / "analysis.toml");
  else
    write_text_atomically(out / "analysis.toml",
                          "# the study deck's [analysis] table, written by pbxmpm study\n" + s.analysis_text);
}

// A run's deck, read from the text the study generated for it (runs/<id>/deck.toml). Its relative
// paths (specimen.packing_dir) resolve against the base deck's folder, where they were written:
// the run's folder or the current one would find nothing.
static Deck run_deck(const StudySpec& s, const std::string& text, const fs::path& file) {
  return Deck::from_string(text, file.string(), fs::path(s.base_deck).parent_path().string());
}

std::vector<std::size_t> runs_of_rank(const std::vector<bool>& pending, int size, int rank) {
  std::vector<std::size_t> mine;
  int k = 0;
  for (std::size_t i = 0; i < pending.size(); ++i)
    if (pending[i] && k++ % size == rank) mine.push_back(i);
  return mine;
}

int check_study(const StudySpec& s) {
  for (const auto& r : s.runs) {
    const std::string text = run_deck_text(s, r);
    Deck deck = run_deck(s, text, fs::path("runs") / r.id / "deck.toml");
    with_study_scene(deck, SceneNotes::print, [](auto&) {});
    deck.check_unused();
  }
  return static_cast<int>(s.runs.size());
}

namespace {

// What became of one run of the study on this rank: failed (the run, or its analysis), and whether
// the study must stop after it (a signal: the run saved a checkpoint, or finished as it came).
struct RunResult {
  bool failed = false, stop = false;
};

// The simulation of one run of the study, in the scene built from its deck: continued from its
// checkpoint when it has a usable one, else from the start.
template <int D>
void simulate_run(const StudySpec& s, const StudyOptions& opt, const Mpi& mpi, const StudyRunSpec& r,
                  const fs::path& dir, const std::string& text, Deck& deck, Scene<D>& scene, int done, int mine) {
  deck.check_unused();
  const fs::path ckpt = dir / "checkpoint.h5";
  const bool restart = fs::exists(ckpt);  // its deck was checked above
  RunOptions ro = run_options_for(deck, (dir / "deck.toml").string(), dir.string());
  ro.threads = opt.threads;
  ro.progress = opt.progress;
  ro.checkpoint_every = opt.checkpoint_every;
  ro.progress_label =
      mpi.size > 1 ? fmt::format("run {}/{} of rank {}, {} runs in the study", done, mine, mpi.rank, s.runs.size())
                   : fmt::format("run {}/{}, {} runs in the study", done, mine, s.runs.size());
  ro.runs_after = mine - done;
  double mass = 0;
  for (double m : scene.particles.mass) mass += m;
  const double rho = scene.die ? mass / scene.die->volume() : 0.0;
  ro.study = {{"study", s.name},
              {"id", r.id},
              {"group", r.group},
              {"key", r.key},
              {"value", r.value_label},
              {"temperature_K", scene.control.temperature},
              {"density_g_cm3", rho / 1000.0},
              {"seed", r.seed}};
  // A checkpoint of this deck that cannot be continued (unreadable, a history.csv shorter than
  // it, history columns of another code version) is set aside and the run starts over.
  bool resumed = false;
  if (restart) {
    Runner<D> runner(scene, ro, true);
    CheckpointData ck;
    try {
      ck = read_checkpoint(ckpt.string());
      runner.resume(ck);
      resumed = true;
    } catch (const InputError& e) {
      const fs::path aside = dir / "checkpoint.unusable.h5";
      fs::rename(ckpt, aside);
      std::fprintf(stderr, "pbxmpm study: %s cannot continue from its checkpoint (%s; moved to %s); starting it over\n",
                   r.id.c_str(), e.what(), aside.c_str());
    }
    if (resumed) {
      std::fprintf(stderr, "pbxmpm study: %s continues from its checkpoint (step %.0f, t = %.4g s, segments: %s)\n",
                   r.id.c_str(), ck.scalars.at("steps"), ck.scalars.at("t"),
                   ck.code_versions.empty() ? "code version not recorded" : ck.code_versions.c_str());
      runner.run();
    }
  }
  if (!resumed) {
    if (restart) {  // the failed resume may have changed the scene: build it again
      Deck again = run_deck(s, text, dir / "deck.toml");
      scene = build_scene<D>(again, SceneNotes::print);
    }
    Runner<D> runner(scene, ro);
    runner.run();
  }
}

// One run of the study: its deck written and built, the run (continued from its checkpoint when it
// has a usable one, else from the start), its analysis. Errors are reported and returned, never
// thrown: the other ranks wait for this one in the collectives after the runs.
RunResult execute_run(const StudySpec& s, const StudyOptions& opt, const Mpi& mpi, const fs::path& out,
                      const StudyRunSpec& r, int done, int mine, double elapsed) {
  RunResult res;
  const fs::path dir = out / "runs" / r.id;
  // Runs of the whole study finished so far, by every rank (read from the shared folder): each
  // rank's own counter alone would not say how far the study is.
  std::string study_done;
  try {
    const auto all = study_status(out.string());
    const auto fin = std::count_if(all.begin(), all.end(), [](const RunStatus& x) { return x.state == "finished"; });
    study_done = fmt::format("{}/{} runs of the study finished", fin, all.size());
  } catch (const std::exception& e) {
    study_done = fmt::format("study status unreadable: {}", e.what());
  }
  std::fprintf(stderr, "pbxmpm study: [%d/%d] %s (rank %d, %s, %.0f s elapsed)\n", done, mine, r.id.c_str(), mpi.rank,
               study_done.c_str(), elapsed);
  try {
    fs::create_directories(dir);
    const std::string text = run_deck_text(s, r);
    write_text_atomically(dir / "deck.toml", text);
    Deck deck = run_deck(s, text, dir / "deck.toml");
    with_study_scene(deck, SceneNotes::print,
                     [&](auto& scene) { simulate_run(s, opt, mpi, r, dir, text, deck, scene, done, mine); });
    const fs::path ckpt = dir / "checkpoint.h5";
    fs::remove(ckpt);  // finished: the study never restarts it
    try {
      analyze_run_to_file(dir.string(), s.analysis);
    } catch (const std::exception& e) {
      // the run itself is whole (run.json "finished"): only its analysis is missing, and the same
      // command re-analyses it without running it again
      res.failed = true;
      std::fprintf(stderr,
                   "pbxmpm study: run %s finished, but its analysis failed: %s (the run is kept; after "
                   "changing the study's [analysis] the same command re-analyses it without running it)\n",
                   r.id.c_str(), e.what());
    }
    if (stop_signal_received()) {
      // the signal came after the run's last checkpoint row, so the run finished: the study
      // stops before the next one (it used to start it, and the signal was forgotten)
      std::fprintf(stderr,
                   "pbxmpm study: a stop signal arrived as run %s finished; the study stops here: run the "
                   "same `pbxmpm study` command to continue it\n",
                   r.id.c_str());
      res.stop = true;
    }
  } catch (const Interrupted& e) {
    // the run saved a checkpoint: the study stops here, and the same command continues it
    res.failed = res.stop = true;
    std::fprintf(stderr,
                 "pbxmpm study: run %s %s; the study stops here: run the same `pbxmpm study` command to "
                 "continue it\n",
                 r.id.c_str(), e.what());
  } catch (const InstabilityError& e) {
    // the run would fail the same way from its checkpoint: a rerun (after a fix) starts it over
    res.failed = true;
    std::error_code ec;  // no throw here: the other ranks wait for this one in the sum below
    fs::remove(dir / "checkpoint.h5", ec);
    std::fprintf(stderr, "pbxmpm study: run %s failed: %s\n", r.id.c_str(), e.what());
  } catch (const std::exception& e) {
    res.failed = true;
    std::fprintf(stderr, "pbxmpm study: run %s failed: %s\n", r.id.c_str(), e.what());
  }
  return res;
}

// Before the first run starts, on this rank: a finished run is reused only if the study still gives
// it the same deck (a changed base deck or override must not be mixed silently with old results),
// and every run to do has its deck built once (specimen included, about a second at 5 um), so that a
// mistyped override in the last run fails now, not hours into the study. Returns how many runs are
// invalid; reports each, throws nothing (the other ranks wait in the sum after it).
int check_before_start(const StudySpec& s, const fs::path& out, const std::vector<std::size_t>& reused,
                       const std::vector<std::size_t>& todo) {
  int invalid = 0;
  for (const std::size_t i : reused) {
    const auto& r = s.runs[i];
    const fs::path dir = out / "runs" / r.id;
    try {  // an exception here must not leave rank 0 alone: the others wait in the sum below
      std::stringstream was;
      was << std::ifstream(dir / "deck.toml").rdbuf();
      const std::string diff = first_difference(was.str(), run_deck_text(s, r));
      if (!diff.empty()) {
        ++invalid;
        std::fprintf(stderr,
                     "pbxmpm study: run %s finished with a different deck than the study gives now (%s); "
                     "delete %s to run it again, or use another --out\n",
                     r.id.c_str(), diff.c_str(), dir.c_str());
      }
    } catch (const std::exception& e) {
      ++invalid;
      std::fprintf(stderr, "pbxmpm study: run %s: %s\n", r.id.c_str(), e.what());
    }
  }
  for (const std::size_t i : todo) {
    const auto& r = s.runs[i];
    try {
      const std::string text = run_deck_text(s, r);
      Deck deck = run_deck(s, text, out / "runs" / r.id / "deck.toml");
      with_study_scene(deck, SceneNotes::quiet, [](auto&) {});  // the run prints the notes when it starts
      deck.check_unused();
      // an interrupted run continues from its checkpoint only if the study still gives its deck;
      // one whose header cannot be read is set aside when the run starts (below), not an error
      const fs::path ckpt = out / "runs" / r.id / "checkpoint.h5";
      std::optional<std::string> saved_deck;
      if (fs::exists(ckpt)) {
        try {
          saved_deck = read_checkpoint_header(ckpt.string()).deck_text;
        } catch (const InputError&) {
        }
      }
      if (saved_deck) {
        const std::string diff = first_difference(*saved_deck, text);
        if (!diff.empty()) {
          ++invalid;
          std::fprintf(stderr,
                       "pbxmpm study: run %s has a checkpoint made from a different deck than the study gives now "
                       "(%s); delete %s to start the run over\n",
                       r.id.c_str(), diff.c_str(), ckpt.c_str());
        }
      }
    } catch (const std::exception& e) {
      ++invalid;
      std::fprintf(stderr, "pbxmpm study: run %s: %s\n", r.id.c_str(), e.what());
    }
  }
  return invalid;
}
}  // namespace

int run_study(const StudySpec& s, const StudyOptions& opt) {
  Mpi mpi;
  const fs::path out = fs::absolute(opt.out_dir);
  // --only names runs of this study (checked before anything is written)
  std::vector<bool> selected(s.runs.size(), opt.only.empty()), pending(s.runs.size(), false);
  for (const auto& id : opt.only) {
    std::size_t i = 0;
    while (i < s.runs.size() && s.runs[i].id != id) ++i;
    if (i == s.runs.size()) {
      std::string ids;
      for (const auto& r : s.runs) ids += (ids.empty() ? "" : ", ") + r.id;
      throw InputError(fmt::format("study {}: --only names run '{}', which the study does not have (its runs: {})",
                                   s.name, id, ids));
    }
    selected[i] = true;
  }
  // One study process per folder: a second one would rewrite study.json, move checkpoints aside and
  // run the same runs. Rank 0 holds the lock for the whole job; every rank stops if it cannot.
  // Everything rank 0 alone does here is caught: a throw on one rank would leave the others waiting
  // in the collective below for ever.
  OutputLock lock;
  int setup_failed = 0;
  if (mpi.rank == 0) {
    try {
      lock = OutputLock(out, "study");
      fs::create_directories(out / "runs");
      write_study_files(s, out);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pbxmpm study: %s\n", e.what());
      setup_failed = 1;
    }
  }
  if (mpi.sum(setup_failed) > 0) return kStudyNotStarted;
  // Which runs this call does: the selected (--only) runs that have not finished. Rank 0 decides
  // and tells the others, so every rank deals the same list even where a shared file system shows
  // the ranks different states of the run folders.
  std::vector<char> is_finished(s.runs.size(), 0);
  if (mpi.rank == 0)
    for (std::size_t i = 0; i < s.runs.size(); ++i) is_finished[i] = finished(out / "runs" / s.runs[i].id);
  mpi.broadcast(is_finished);
  for (std::size_t i = 0; i < s.runs.size(); ++i) pending[i] = selected[i] && !is_finished[i];
  const std::vector<std::size_t> todo = runs_of_rank(pending, mpi.size, mpi.rank);
  // Every finished run, selected or not (the report will use them all), is checked against the
  // deck the study gives now and re-analysed (cheap) by rank 0, so that a changed [analysis] table
  // applies to it.
  std::vector<std::size_t> reused;
  for (std::size_t i = 0; i < s.runs.size(); ++i)
    if (is_finished[i] && mpi.rank == 0) reused.push_back(i);
  // every deck checked before the first run starts
  const int invalid = mpi.sum(check_before_start(s, out, reused, todo));
  if (invalid > 0) {
    if (mpi.rank == 0)
      std::fprintf(stderr, "pbxmpm study: %d %s with an invalid or changed deck; no run started\n", invalid,
                   invalid == 1 ? "run" : "runs");
    return kStudyNotStarted;
  }
  const auto t0 = std::chrono::steady_clock::now();
  int failed = 0, done = 0;
  bool interrupted = false;
  for (const std::size_t i : reused) {
    const auto& r = s.runs[i];
    std::fprintf(stderr, "pbxmpm study: %s already finished, skipped (re-analysed)\n", r.id.c_str());
    try {
      analyze_run_to_file((out / "runs" / r.id).string(), s.analysis);
    } catch (const std::exception& e) {
      ++failed;
      std::fprintf(stderr, "pbxmpm study: run %s: analysis failed: %s\n", r.id.c_str(), e.what());
    }
  }
  const int mine = static_cast<int>(todo.size());
  for (const std::size_t i : todo) {
    ++done;
    const RunResult res = execute_run(s, opt, mpi, out, s.runs[i], done, mine,
                                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    failed += res.failed;
    if (res.stop) {
      interrupted = true;
      break;
    }
  }
  failed = mpi.sum(failed);
  mpi.barrier();
  if (mpi.sum(interrupted ? 1 : 0) > 0) return kStudyInterrupted;
  if (mpi.rank == 0) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    int ran = 0;
    for (const bool p : pending) ran += p;
    // the runs this command attempted; the others finished before or were left out by --only
    std::fprintf(stderr, "pbxmpm study: %d of the study's %zu runs attempted now, %d failed, %.0f s\n", ran,
                 s.runs.size(), failed, elapsed);
    std::string missing;
    for (const auto& r : s.runs)
      if (!finished(out / "runs" / r.id)) missing += (missing.empty() ? "" : ", ") + r.id;
    if (opt.report && failed == 0 && !missing.empty())
      std::fprintf(stderr,
                   "pbxmpm study: no report yet: runs not finished: %s (`pbxmpm report %s --partial` reports the "
                   "finished ones)\n",
                   missing.c_str(), out.c_str());
    if (opt.report && failed == 0 && missing.empty()) {
      ReportOptions rep;
      rep.fits.reuse_analysis = true;
      rep.fits.analysis = s.analysis;
      rep.fits.run_phases = run_phases_for_bounds;
      const std::string dir = build_report(out.string(), rep);
      std::fprintf(stderr, "pbxmpm study: report in %s/report.html\n", dir.c_str());
    }
  }
  return failed;
}

void apply_set_options(StudySpec& s, const std::vector<std::string>& set) {
  for (const auto& text : set) {
    const DeckOverride ov = parse_override_option(text);
    if (ov.first == "specimen.seed" || ov.first == "packing.seed")
      throw InputError(
          fmt::format("--set '{}': a study gives each run its seed (study.seeds or a group's seeds)", ov.first));
    for (auto& r : s.runs) {
      // a run's overrides end with its group's key and its seed (read_study)
      if (r.set.size() < 2) throw std::logic_error("a study run without its group key and seed");
      if (r.set[r.set.size() - 2].first == ov.first)
        throw InputError(fmt::format("--set '{}': group '{}' varies this key", ov.first, r.group));
      r.set.insert(r.set.end() - 2, ov);
    }
  }
}

}  // namespace pbx
