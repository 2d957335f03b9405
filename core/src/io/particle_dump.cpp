#include "io/particle_dump.hpp"

#include <hdf5.h>

#include <stdexcept>
#include <string>

namespace sphforge::io {

namespace {

/// Closes an HDF5 handle at scope exit.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

hid_t check(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: cannot " + what);
  return id;
}

void attribute(hid_t object, const char* name, hid_t type, const void* value) {
  Handle space{check(H5Screate(H5S_SCALAR), "create a scalar space"), H5Sclose};
  Handle attr{check(H5Acreate2(object, name, type, space.id, H5P_DEFAULT, H5P_DEFAULT), "create an attribute"),
              H5Aclose};
  if (H5Awrite(attr.id, type, value) < 0) throw std::runtime_error(std::string("HDF5: cannot write ") + name);
}

void string_attribute(hid_t object, const char* name, const std::string& value) {
  Handle type{check(H5Tcopy(H5T_C_S1), "copy a string type"), H5Tclose};
  H5Tset_size(type.id, value.size() + 1);
  attribute(object, name, type.id, value.c_str());
}

}  // namespace

void write_particle_dump(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                         double time_s, long long step, const std::vector<ParticleArray>& extra) {
  Handle f{check(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create " + file.string()),
           H5Fclose};
  attribute(f.id, "time_s", H5T_NATIVE_DOUBLE, &time_s);
  attribute(f.id, "step", H5T_NATIVE_LLONG, &step);
  const unsigned long long particles = count;
  attribute(f.id, "particles", H5T_NATIVE_ULLONG, &particles);
  Handle group{check(H5Gcreate2(f.id, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "create /fields"),
               H5Gclose};
  for (const std::string& name : fields.names()) {
    if (!fields.allocated(name)) continue;
    const FieldInfo& info = fields.info(name);
    const hsize_t dims[2] = {count, static_cast<hsize_t>(info.components)};
    Handle space{check(H5Screate_simple(2, dims, nullptr), "create a data space"), H5Sclose};
    const bool integer = info.type == FieldType::Int64;
    const hid_t type = integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
    Handle data{check(H5Dcreate2(group.id, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      "create dataset " + name),
                H5Dclose};
    const void* values = integer ? static_cast<const void*>(fields.i64(name)) : static_cast<const void*>(fields.f64(name));
    if (count > 0 && H5Dwrite(data.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values) < 0)
      throw std::runtime_error("HDF5: cannot write dataset " + name);
    string_attribute(data.id, "unit", info.unit);
  }
  for (const ParticleArray& e : extra) {
    if (e.values.size() != count * static_cast<std::size_t>(e.components))
      throw std::logic_error("write_particle_dump: array '" + e.name + "' does not hold " + std::to_string(count) +
                             " particles");
    const hsize_t dims[2] = {count, static_cast<hsize_t>(e.components)};
    Handle space{check(H5Screate_simple(2, dims, nullptr), "create a data space"), H5Sclose};
    Handle data{check(H5Dcreate2(group.id, e.name.c_str(), H5T_NATIVE_DOUBLE, space.id, H5P_DEFAULT, H5P_DEFAULT,
                                 H5P_DEFAULT),
                      "create dataset " + e.name),
                H5Dclose};
    if (count > 0 && H5Dwrite(data.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.values.data()) < 0)
      throw std::runtime_error("HDF5: cannot write dataset " + e.name);
    string_attribute(data.id, "unit", e.unit);
  }
}

}  // namespace sphforge::io
