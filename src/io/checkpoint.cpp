#include "io/checkpoint.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <hdf5.h>

#include "core/error.hpp"
#include "io/hdf5_image.hpp"

namespace pbx {

namespace {
constexpr const char* kFormat = "pbxmpm-checkpoint-1";

// FNV-1a (64 bit) over every stored value, names included: a flipped bit anywhere in the data a
// restart reads changes it. Not a defence against tampering, which a checkpoint does not need.
class Fnv1a {
 public:
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h_ ^= b[i];
      h_ *= 1099511628211ull;
    }
  }
  void text(const std::string& s) {
    const std::uint64_t n = s.size();
    bytes(&n, sizeof n);
    bytes(s.data(), s.size());
  }
  std::string hex() const { return fmt::format("fnv1a64:{:016x}", h_); }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

std::string checksum(const CheckpointData& c) {
  Fnv1a h;
  h.text(c.deck_text);
  h.text(c.deck_name);
  h.text(c.code_versions);
  h.text(c.run_id);
  for (const auto& [k, v] : c.scalars) {
    h.text(k);
    h.bytes(&v, sizeof v);
  }
  for (const auto& [k, v] : c.arrays) {
    h.text(k);
    const std::uint64_t n = v.size();
    h.bytes(&n, sizeof n);
    h.bytes(v.data(), v.size() * sizeof(double));
  }
  return h.hex();
}

bool write_string(hid_t loc, const char* name, const std::string& s) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t type = H5Tcopy(H5T_C_S1);
  bool ok = space >= 0 && type >= 0 && H5Tset_size(type, s.size() + 1) >= 0;
  hid_t a = ok ? H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT) : -1;
  ok = a >= 0 && H5Awrite(a, type, s.c_str()) >= 0;
  if (a >= 0) ok = H5Aclose(a) >= 0 && ok;
  if (type >= 0) H5Tclose(type);
  if (space >= 0) H5Sclose(space);
  return ok;
}

// Reading: every call checked; the first failure names the checkpoint and what could not be read.
struct Reader {
  const std::string& file;
  [[noreturn]] void damaged(const std::string& what) const {
    throw InputError(fmt::format("checkpoint '{}' is damaged ({}): the run cannot continue from it", file, what));
  }
  std::string string(hid_t loc, const char* name) const {
    hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
    if (a < 0) damaged(fmt::format("attribute '{}' unreadable", name));
    hid_t type = H5Aget_type(a);
    const std::size_t n = type >= 0 ? H5Tget_size(type) : 0;
    std::string s(n, '\0');
    const bool ok = n > 0 && H5Tget_class(type) == H5T_STRING && H5Aread(a, type, s.data()) >= 0;
    if (type >= 0) H5Tclose(type);
    H5Aclose(a);
    if (!ok) damaged(fmt::format("attribute '{}' unreadable", name));
    s.resize(std::strlen(s.c_str()));
    return s;
  }
};
}  // namespace

void write_checkpoint(const std::string& file, const CheckpointData& c) {
  // Built in memory and written whole under a temporary name, then renamed: a run killed or a
  // disk filled mid-write keeps the previous checkpoint (io/hdf5_image.hpp).
  Hdf5Quiet quiet;
  Hdf5Image img(file);
  const hid_t f = img.id();
  bool ok = write_string(f, "deck_text", c.deck_text);
  ok = write_string(f, "deck_name", c.deck_name) && ok;
  ok = write_string(f, "code_versions", c.code_versions) && ok;
  ok = write_string(f, "run_id", c.run_id) && ok;
  ok = write_string(f, "format", kFormat) && ok;
  ok = write_string(f, "checksum", checksum(c)) && ok;
  hid_t gs = H5Gcreate2(f, "scalars", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ok = gs >= 0 && ok;
  for (const auto& [k, v] : c.scalars) {
    if (gs < 0) break;
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = space < 0 ? -1 : H5Acreate2(gs, k.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    ok = a >= 0 && H5Awrite(a, H5T_NATIVE_DOUBLE, &v) >= 0 && ok;
    if (a >= 0) ok = H5Aclose(a) >= 0 && ok;
    if (space >= 0) H5Sclose(space);
  }
  if (gs >= 0) ok = H5Gclose(gs) >= 0 && ok;
  for (const auto& [k, v] : c.arrays) {
    hsize_t n = v.size();
    hid_t space = H5Screate_simple(1, &n, nullptr);
    hid_t ds =
        space < 0 ? -1 : H5Dcreate2(f, k.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ok = ds >= 0 && ok;
    if (ds >= 0 && n > 0) ok = H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0 && ok;
    if (ds >= 0) ok = H5Dclose(ds) >= 0 && ok;
    if (space >= 0) H5Sclose(space);
  }
  if (!ok) throw OutputError(fmt::format("cannot write checkpoint '{}': HDF5 could not build it in memory", file));
  img.save();
}

namespace {
// Opens a checkpoint read-only, or throws naming the file when it is missing or not a checkpoint.
hid_t open_checkpoint(const std::string& file) {
  if (!std::filesystem::exists(file)) throw InputError(fmt::format("checkpoint '{}' does not exist", file));
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0 || H5Aexists(f, "format") <= 0 || Reader{file}.string(f, "format") != kFormat) {
    if (f >= 0) H5Fclose(f);
    throw InputError(fmt::format("'{}' is not a pbxmpm checkpoint (or its header is damaged)", file));
  }
  return f;
}

// The whole checkpoint, or (arrays = false) all but the particle arrays.
CheckpointData read_open(hid_t f, const std::string& file, bool arrays) {
  const Reader rd{file};
  CheckpointData c;
  c.deck_text = rd.string(f, "deck_text");
  c.deck_name = rd.string(f, "deck_name");
  if (H5Aexists(f, "code_versions") > 0) c.code_versions = rd.string(f, "code_versions");
  if (H5Aexists(f, "run_id") > 0) c.run_id = rd.string(f, "run_id");
  hid_t gs = H5Gopen2(f, "scalars", H5P_DEFAULT);
  if (gs < 0) rd.damaged("group 'scalars' unreadable");
  H5O_info_t info;
  if (H5Oget_info2(gs, &info, H5O_INFO_NUM_ATTRS) < 0) rd.damaged("group 'scalars' unreadable");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    hid_t a = H5Aopen_by_idx(gs, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT);
    char name[256] = {};
    double v = 0;
    const bool ok = a >= 0 && H5Aget_name(a, sizeof name, name) > 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &v) >= 0;
    if (a >= 0) H5Aclose(a);
    if (!ok) rd.damaged(fmt::format("scalar {} unreadable", i));
    c.scalars[name] = v;
  }
  H5Gclose(gs);
  H5G_info_t ginfo;
  if (H5Gget_info(f, &ginfo) < 0) rd.damaged("root group unreadable");
  for (hsize_t i = 0; arrays && i < ginfo.nlinks; ++i) {
    char name[256] = {};
    if (H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) <= 0)
      rd.damaged(fmt::format("dataset name {} unreadable", i));
    if (std::string(name) == "scalars") continue;
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    hid_t space = ds < 0 ? -1 : H5Dget_space(ds);
    hsize_t n = 0;
    bool ok =
        space >= 0 && H5Sget_simple_extent_ndims(space) == 1 && H5Sget_simple_extent_dims(space, &n, nullptr) == 1;
    std::vector<double> v;
    if (ok && n > (hsize_t{1} << 36)) ok = false;  // a damaged size, not a real array of 550 GB
    if (ok) {
      v.resize(n);
      if (n > 0) ok = H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0;
    }
    if (space >= 0) H5Sclose(space);
    if (ds >= 0) H5Dclose(ds);
    if (!ok) rd.damaged(fmt::format("dataset '{}' unreadable", name));
    c.arrays[name] = std::move(v);
  }
  if (arrays) {
    if (H5Aexists(f, "checksum") <= 0)
      throw InputError(
          fmt::format("checkpoint '{}' has no checksum (written before 2026-12-04): its data cannot be "
                      "verified, so the run cannot continue from it; rerun from the start",
                      file));
    const std::string stored = rd.string(f, "checksum");
    if (stored != checksum(c))
      rd.damaged(fmt::format("its checksum {} does not match its contents, {}: a changed or truncated copy", stored,
                             checksum(c)));
  }
  return c;
}

CheckpointData read_parts(const std::string& file, bool arrays) {
  Hdf5Quiet quiet;
  hid_t f = open_checkpoint(file);
  try {
    CheckpointData c = read_open(f, file, arrays);
    H5Fclose(f);
    return c;
  } catch (...) {
    H5Fclose(f);
    throw;
  }
}
}  // namespace

CheckpointData read_checkpoint_header(const std::string& file) { return read_parts(file, false); }

CheckpointData read_checkpoint(const std::string& file) { return read_parts(file, true); }

}  // namespace pbx
