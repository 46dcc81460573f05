#pragma once
// Checkpoints: the complete state of a run in one HDF5 file (particles, material histories,
// clock, energy accumulators, the runner's reporting state, and the deck text to rebuild the
// scene). A run restarted from a checkpoint continues bit for bit as if it had not stopped.
#include <map>
#include <string>
#include <vector>

namespace pbx {

struct CheckpointData {
  std::string deck_text, deck_name;
  std::string code_versions;  // of the run's segments so far, "; "-separated ("" before 2026-12-02)
  std::string run_id;         // the run's identity (run.json "run_id"): a restart writes only into its own run's folder
  std::map<std::string, double> scalars;              // clock, energies, runner state
  std::map<std::string, std::vector<double>> arrays;  // flattened particle/material arrays
};

// Written whole or not at all (throws OutputError, the previous file kept), with a checksum of
// every stored value.
void write_checkpoint(const std::string& file, const CheckpointData& c);
// Throws InputError when the file is missing, not a checkpoint, unreadable, or its checksum does
// not match its contents (a flipped bit, a truncated copy).
CheckpointData read_checkpoint(const std::string& file);
// Everything but the particle arrays (cheap: a few kB of a file of hundreds of MB): to check a
// checkpoint belongs to a deck, or to say how far its run got.
CheckpointData read_checkpoint_header(const std::string& file);

}  // namespace pbx
