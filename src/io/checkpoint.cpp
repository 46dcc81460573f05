#include "io/checkpoint.hpp"

#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <hdf5.h>

#include "core/error.hpp"

namespace pbx {

namespace {
// Returns false when any HDF5 call failed (a full disk, a quota), so the checkpoint is not used.
bool write_string(hid_t loc, const char* name, const std::string& s) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, s.size() + 1);
  hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = space >= 0 && type >= 0 && a >= 0 && H5Awrite(a, type, s.c_str()) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Tclose(type);
  H5Sclose(space);
  return ok;
}
std::string read_string(hid_t loc, const char* name) {
  hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  hid_t type = H5Aget_type(a);
  std::string s(H5Tget_size(type), '\0');
  H5Aread(a, type, s.data());
  H5Tclose(type);
  H5Aclose(a);
  s.resize(std::strlen(s.c_str()));
  return s;
}
}  // namespace

void write_checkpoint(const std::string& file, const CheckpointData& c) {
  // write to a temporary name, then rename: a run killed mid-write leaves the previous checkpoint
  const std::string tmp = file + ".tmp";
  hid_t f = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f < 0) throw InputError(fmt::format("cannot write checkpoint '{}'", file));
  bool ok = write_string(f, "deck_text", c.deck_text);
  ok = write_string(f, "deck_name", c.deck_name) && ok;
  ok = write_string(f, "code_versions", c.code_versions) && ok;
  ok = write_string(f, "format", "pbxmpm-checkpoint-1") && ok;
  hid_t gs = H5Gcreate2(f, "scalars", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ok = gs >= 0 && ok;
  for (const auto& [k, v] : c.scalars) {
    if (gs < 0) break;
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(gs, k.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    ok = a >= 0 && H5Awrite(a, H5T_NATIVE_DOUBLE, &v) >= 0 && ok;
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
  }
  if (gs >= 0) H5Gclose(gs);
  for (const auto& [k, v] : c.arrays) {
    hsize_t n = v.size();
    hid_t space = H5Screate_simple(1, &n, nullptr);
    hid_t ds = H5Dcreate2(f, k.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ok = ds >= 0 && ok;
    if (ds >= 0 && n > 0) ok = H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0 && ok;
    if (ds >= 0) H5Dclose(ds);
    H5Sclose(space);
  }
  ok = H5Fclose(f) >= 0 && ok;
  // Only a checkpoint written whole replaces the previous one: a failed write (full disk) keeps
  // the last good checkpoint and says so.
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(fmt::format("cannot write checkpoint '{}' (disk full?): the previous checkpoint is kept", file));
  }
  std::filesystem::rename(tmp, file);
}

namespace {
// Opens a checkpoint read-only, or throws naming the file when it is missing or not a checkpoint.
hid_t open_checkpoint(const std::string& file) {
  if (!std::filesystem::exists(file)) throw InputError(fmt::format("checkpoint '{}' does not exist", file));
  H5E_auto2_t old_func;
  void* old_data;
  H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Eset_auto2(H5E_DEFAULT, old_func, old_data);
  if (f < 0 || H5Aexists(f, "format") <= 0 || read_string(f, "format") != "pbxmpm-checkpoint-1") {
    if (f >= 0) H5Fclose(f);
    throw InputError(fmt::format("'{}' is not a pbxmpm checkpoint", file));
  }
  return f;
}

// The whole checkpoint, or (arrays = false) all but the particle arrays.
CheckpointData read_parts(const std::string& file, bool arrays) {
  hid_t f = open_checkpoint(file);
  CheckpointData c;
  c.deck_text = read_string(f, "deck_text");
  c.deck_name = read_string(f, "deck_name");
  if (H5Aexists(f, "code_versions") > 0) c.code_versions = read_string(f, "code_versions");
  hid_t gs = H5Gopen2(f, "scalars", H5P_DEFAULT);
  H5O_info_t info;
  H5Oget_info2(gs, &info, H5O_INFO_NUM_ATTRS);
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    hid_t a = H5Aopen_by_idx(gs, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT);
    char name[256];
    H5Aget_name(a, sizeof name, name);
    double v = 0;
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    c.scalars[name] = v;
    H5Aclose(a);
  }
  H5Gclose(gs);
  H5G_info_t ginfo;
  H5Gget_info(f, &ginfo);
  for (hsize_t i = 0; arrays && i < ginfo.nlinks; ++i) {
    char name[256];
    H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
    if (std::string(name) == "scalars") continue;
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    hid_t space = H5Dget_space(ds);
    hsize_t n = 0;
    H5Sget_simple_extent_dims(space, &n, nullptr);
    std::vector<double> v(n);
    if (n > 0) H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    c.arrays[name] = std::move(v);
    H5Sclose(space);
    H5Dclose(ds);
  }
  H5Fclose(f);
  return c;
}
}  // namespace

CheckpointData read_checkpoint_header(const std::string& file) { return read_parts(file, false); }

CheckpointData read_checkpoint(const std::string& file) { return read_parts(file, true); }

}  // namespace pbx
