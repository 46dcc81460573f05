#include <CLI/CLI.hpp>

#include "app/commands.hpp"

namespace pbx::app {
void register_run(CLI::App&) {}
}  // namespace pbx::app
