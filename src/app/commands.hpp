#pragma once
// Each `pbxmpm` sub-command lives in its own file (cmd_<name>.cpp) and registers itself here.
namespace CLI {
class App;
}

namespace pbx::app {
void register_run(CLI::App& app);       // run, check        (cmd_run.cpp)
void register_material(CLI::App& app);  // material driver   (cmd_material.cpp)
void register_pack(CLI::App& app);      // mesostructures    (cmd_pack.cpp)
void register_analysis(CLI::App& app);  // analyze, fit, report (cmd_analysis.cpp)
void register_study(CLI::App& app);     // study             (cmd_study.cpp)
}  // namespace pbx::app
