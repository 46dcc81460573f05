#pragma once
// An HDF5 file built in memory (HDF5's core driver, no backing store) and put on the disk by
// write_bytes_atomically: whole or not at all, every error checked and named. HDF5 writing
// straight to a full disk reported the failure only at close, left a half file, and then crashed
// at exit (HDF5 1.10.8 keeps a file whose close failed and its exit handler faults on it).
#include <string>

#include <hdf5.h>

namespace pbx {

class Hdf5Image {
 public:
  explicit Hdf5Image(std::string target);  // the file it will become (for the messages)
  ~Hdf5Image();
  Hdf5Image(const Hdf5Image&) = delete;
  Hdf5Image& operator=(const Hdf5Image&) = delete;
  hid_t id() const { return f_; }
  // Closes the in-memory file and writes its bytes to the target; throws OutputError.
  void save();

 private:
  std::string target_;
  hid_t f_ = -1;
};

// Silences HDF5's error stack printing while alive (the callers check every return and say
// what failed in one line instead of a 20-40 line dump).
class Hdf5Quiet {
 public:
  Hdf5Quiet();
  ~Hdf5Quiet();
  Hdf5Quiet(const Hdf5Quiet&) = delete;
  Hdf5Quiet& operator=(const Hdf5Quiet&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

}  // namespace pbx
