// Placeholder registration; the sub-commands of this file are added by their module's issue.
#include <CLI/CLI.hpp>

#include "app/commands.hpp"

namespace pbx::app {
void register_analysis(CLI::App&) {}
}  // namespace pbx::app
