#pragma once
// A run's identity: run.json and every checkpoint carry it, so that a restart refuses a folder
// holding another run.
#include <filesystem>
#include <random>
#include <string>

#include <fmt/format.h>

#include "io/json.hpp"

namespace pbx {

// A fresh run's identity.
inline std::string new_run_id() {
  std::random_device rd;
  return fmt::format("{:08x}{:08x}", rd(), rd());
}

// The run_id a folder's run.json records, or "" (no run.json, or one written before 2026-12-04).
inline std::string run_id_in(const std::filesystem::path& dir) {
  if (!std::filesystem::exists(dir / "run.json")) return "";
  const Json run = json_read_file((dir / "run.json").string());
  const Json* id = json_find(run, "run_id");
  return id && id->is_string() ? id->get<std::string>() : std::string();
}

}  // namespace pbx
