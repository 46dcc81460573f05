#include "io/snapshot.hpp"

#include <filesystem>
#include <cstring>
#include <sstream>

#include <fmt/format.h>
#include <hdf5.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"
#include "io/hdf5_image.hpp"

namespace pbx {

namespace {
// Every HDF5 call is checked; the file is built in memory and reaches the disk whole
// (io/hdf5_image.hpp): a snapshot that could not be written (disk full, quota) stops the run with
// a message naming it, and leaves no half file.
void write_dataset(hid_t file, const std::string& path, const char* name, hid_t type, const void* data,
                   std::size_t rows, std::size_t cols, const char* units) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  hid_t ds = space < 0 ? -1 : H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = ds >= 0 && (rows == 0 || H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0);
  if (ok) {
    hid_t aspace = H5Screate(H5S_SCALAR);
    hid_t atype = H5Tcopy(H5T_C_S1);
    H5Tset_size(atype, std::strlen(units) + 1);
    hid_t attr = H5Acreate2(ds, "units", atype, aspace, H5P_DEFAULT, H5P_DEFAULT);
    ok = attr >= 0 && H5Awrite(attr, atype, units) >= 0;
    if (attr >= 0) H5Aclose(attr);
    H5Tclose(atype);
    H5Sclose(aspace);
  }
  if (ds >= 0) ok = H5Dclose(ds) >= 0 && ok;
  if (space >= 0) H5Sclose(space);
  if (!ok) throw OutputError(fmt::format("cannot write snapshot '{}': writing dataset '{}' failed", path, name));
}
}  // namespace

std::string SnapshotWriter::snapshot_name(std::size_t i) { return fmt::format("snap_{:04d}.h5", i); }

void SnapshotWriter::write(const SnapshotData& s) {
  std::filesystem::create_directories(dir_);
  const std::string name = snapshot_name(entries_.size());
  const std::string path = (std::filesystem::path(dir_) / name).string();
  Hdf5Quiet quiet;
  Hdf5Image img(path);
  const hid_t f = img.id();
  const std::size_t n = s.count;
  write_dataset(f, path, "position", H5T_NATIVE_DOUBLE, s.position.data(), n, 3, "m");
  write_dataset(f, path, "velocity", H5T_NATIVE_DOUBLE, s.velocity.data(), n, 3, "m/s");
  write_dataset(f, path, "stress", H5T_NATIVE_DOUBLE, s.stress.data(), n, 6,
                "Pa (xx, xy, xz, yy, yz, zz: the XDMF Tensor6 order), tension positive");
  write_dataset(f, path, "pressure", H5T_NATIVE_DOUBLE, s.pressure.data(), n, 1, "Pa, -tr(sigma)/3");
  write_dataset(f, path, "von_mises", H5T_NATIVE_DOUBLE, s.von_mises.data(), n, 1, "Pa");
  write_dataset(f, path, "plastic_strain", H5T_NATIVE_DOUBLE, s.plastic_strain.data(), n, 1, "1");
  write_dataset(f, path, "volume", H5T_NATIVE_DOUBLE, s.volume.data(), n, 1, s.dim == 2 ? "m^2 per m of depth" : "m^3");
  write_dataset(f, path, "material", H5T_NATIVE_INT, s.material.data(), n, 1, "index into run.json materials");
  write_dataset(f, path, "field", H5T_NATIVE_INT, s.field.data(), n, 1, "contact field index");
  if (s.rigid_count > 0) {
    write_dataset(f, path, "rigid_position", H5T_NATIVE_DOUBLE, s.rigid_position.data(), s.rigid_count, 3, "m");
    std::string names;
    for (std::size_t b = 0; b < s.rigid_body_names.size(); ++b)
      names += fmt::format("{}{}={}", b ? ", " : "", b, s.rigid_body_names[b]);
    write_dataset(f, path, "rigid_body", H5T_NATIVE_INT, s.rigid_body.data(), s.rigid_count, 1,
                  ("rigid body index: " + names).c_str());
  }
  hid_t aspace = H5Screate(H5S_SCALAR);
  hid_t attr = aspace < 0 ? -1 : H5Acreate2(f, "time_s", H5T_NATIVE_DOUBLE, aspace, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = attr >= 0 && H5Awrite(attr, H5T_NATIVE_DOUBLE, &s.time) >= 0;
  if (attr >= 0) ok = H5Aclose(attr) >= 0 && ok;
  if (aspace >= 0) H5Sclose(aspace);
  if (!ok) throw OutputError(fmt::format("cannot write snapshot '{}': writing attribute 'time_s' failed", path));
  img.save();
  entries_.push_back({name, s.time, n, s.rigid_count});
  write_xdmf();
}

void SnapshotWriter::write_xdmf() const {
  // replaced whole: a run killed mid-write keeps the previous sidecar
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
       "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& e : entries_) {
    const auto n = e.count;
    x << fmt::format("<Grid Name=\"t\" GridType=\"Collection\" CollectionType=\"Spatial\"><Time Value=\"{:.10g}\"/>\n",
                     e.time);
    x << "<Grid Name=\"particles\" GridType=\"Uniform\">\n";
    x << fmt::format("<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\"/>\n", n);
    x << fmt::format(
        "<Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{}:/position</DataItem></Geometry>\n",
        n, e.file);
    auto attr = [&](const char* name, const char* type, int cols, const char* num, int prec, std::size_t rows) {
      const std::string dims = cols == 1 ? fmt::format("{}", rows) : fmt::format("{} {}", rows, cols);
      x << fmt::format(
          "<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\"><DataItem Dimensions=\"{}\" "
          "NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:/{}</DataItem></Attribute>\n",
          name, type, dims, num, prec, e.file, name);
    };
    attr("velocity", "Vector", 3, "Float", 8, n);
    attr("stress", "Tensor6", 6, "Float", 8, n);
    attr("pressure", "Scalar", 1, "Float", 8, n);
    attr("von_mises", "Scalar", 1, "Float", 8, n);
    attr("plastic_strain", "Scalar", 1, "Float", 8, n);
    attr("volume", "Scalar", 1, "Float", 8, n);
    attr("material", "Scalar", 1, "Int", 4, n);
    attr("field", "Scalar", 1, "Int", 4, n);
    x << "</Grid>\n";
    if (e.rigid_count > 0) {
      x << "<Grid Name=\"rigid_bodies\" GridType=\"Uniform\">\n";
      x << fmt::format("<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\"/>\n",
                       e.rigid_count);
      x << fmt::format(
          "<Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">{}:/rigid_position</DataItem></Geometry>\n",
          e.rigid_count, e.file);
      attr("rigid_body", "Scalar", 1, "Int", 4, e.rigid_count);
      x << "</Grid>\n";
    }
    x << "</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  write_text_atomically(std::filesystem::path(dir_) / "snapshots.xmf", x.str());
}

}  // namespace pbx
