#include "io/hdf5_image.hpp"

#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"

namespace pbx {

Hdf5Quiet::Hdf5Quiet() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}
Hdf5Quiet::~Hdf5Quiet() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

Hdf5Image::Hdf5Image(std::string target) : target_(std::move(target)) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  // grows in 4 MiB pieces; nothing is written behind our back (no backing store)
  if (fapl >= 0 && H5Pset_fapl_core(fapl, 4u << 20, 0) >= 0)
    f_ = H5Fcreate(target_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  if (fapl >= 0) H5Pclose(fapl);
  if (f_ < 0) throw OutputError(fmt::format("cannot write '{}': HDF5 could not create the file in memory", target_));
}

Hdf5Image::~Hdf5Image() {
  if (f_ >= 0) H5Fclose(f_);
}

void Hdf5Image::save() {
  const bool flushed = H5Fflush(f_, H5F_SCOPE_GLOBAL) >= 0;
  const ssize_t size = flushed ? H5Fget_file_image(f_, nullptr, 0) : -1;
  std::vector<char> bytes(size > 0 ? static_cast<std::size_t>(size) : 0);
  const bool ok = size > 0 && H5Fget_file_image(f_, bytes.data(), bytes.size()) == size;
  const herr_t closed = H5Fclose(f_);
  f_ = -1;
  if (!ok || closed < 0)
    throw OutputError(fmt::format("cannot write '{}': HDF5 could not finish the file in memory", target_));
  write_bytes_atomically(target_, bytes.data(), bytes.size());
}

}  // namespace pbx
