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

/// The layout both files share: root attributes time_s, step, particles; /fields/<name>.
void write_particles(hid_t f, const FieldRegistry& fields, std::size_t count, double time_s, long long step,
                     const std::vector<ParticleArray>& extra) {
  attribute(f, "time_s", H5T_NATIVE_DOUBLE, &time_s);
  attribute(f, "step", H5T_NATIVE_LLONG, &step);
  const unsigned long long particles = count;
  attribute(f, "particles", H5T_NATIVE_ULLONG, &particles);
  Handle group{check(H5Gcreate2(f, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "create /fields"), H5Gclose};
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

}  // namespace

void write_particle_dump(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                         double time_s, long long step, const std::vector<ParticleArray>& extra) {
  Handle f{check(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create " + file.string()),
           H5Fclose};
  write_particles(f.id, fields, count, time_s, step, extra);
}

void write_checkpoint(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                      double time_s, long long step, const std::string& state_json,
                      const std::vector<ParticleArray>& extra) {
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  {
    Handle f{check(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "create " + tmp.string()),
             H5Fclose};
    write_particles(f.id, fields, count, time_s, step, extra);
    const int version = kCheckpointFormat;
    attribute(f.id, "checkpoint_format", H5T_NATIVE_INT, &version);
    // The state is JSON text in a 1-D char dataset: an attribute would be limited to 64 KiB.
    const hsize_t length = state_json.size();
    Handle space{check(H5Screate_simple(1, &length, nullptr), "create a data space"), H5Sclose};
    Handle data{check(H5Dcreate2(f.id, "state", H5T_NATIVE_CHAR, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      "create dataset state"),
                H5Dclose};
    if (length > 0 && H5Dwrite(data.id, H5T_NATIVE_CHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, state_json.data()) < 0)
      throw std::runtime_error("HDF5: cannot write dataset state");
  }
  // Only a complete file takes the checkpoint's name: a run killed while writing leaves the
  // earlier checkpoints as they were.
  std::filesystem::rename(tmp, file);
}

std::string read_checkpoint(const std::filesystem::path& file, FieldRegistry& fields, std::size_t count,
                            std::vector<ParticleArray>& extra) {
  // HDF5 prints its own error stack to stderr by default; the messages below say what went wrong.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (!std::filesystem::is_regular_file(file)) throw std::runtime_error("no such file");
  Handle f{check(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open it as an HDF5 file"), H5Fclose};
  if (H5Aexists(f.id, "checkpoint_format") <= 0)
    throw std::runtime_error("not a sphforge checkpoint (no attribute checkpoint_format)");
  int version = 0;
  {
    Handle a{check(H5Aopen(f.id, "checkpoint_format", H5P_DEFAULT), "open attribute checkpoint_format"), H5Aclose};
    H5Aread(a.id, H5T_NATIVE_INT, &version);
  }
  if (version != kCheckpointFormat)
    throw std::runtime_error("checkpoint format " + std::to_string(version) + ", this build reads " +
                             std::to_string(kCheckpointFormat));
  unsigned long long particles = 0;
  {
    Handle a{check(H5Aopen(f.id, "particles", H5P_DEFAULT), "open attribute particles"), H5Aclose};
    H5Aread(a.id, H5T_NATIVE_ULLONG, &particles);
  }
  if (particles != count)
    throw std::runtime_error("it holds " + std::to_string(particles) + " particles, the case builds " +
                             std::to_string(count));
  Handle group{check(H5Gopen2(f.id, "fields", H5P_DEFAULT), "open /fields"), H5Gclose};
  // One dataset of `components` numbers per particle into `values`.
  auto read = [&](const std::string& name, int components, hid_t type, void* values) {
    if (H5Lexists(group.id, name.c_str(), H5P_DEFAULT) <= 0)
      throw std::runtime_error("it has no field '" + name + "' (written by another case or version?)");
    Handle data{check(H5Dopen2(group.id, name.c_str(), H5P_DEFAULT), "open dataset " + name), H5Dclose};
    Handle space{check(H5Dget_space(data.id), "read the shape of " + name), H5Sclose};
    hsize_t dims[2] = {0, 0};
    if (H5Sget_simple_extent_ndims(space.id) != 2 || H5Sget_simple_extent_dims(space.id, dims, nullptr) != 2 ||
        dims[0] != count || dims[1] != static_cast<hsize_t>(components))
      throw std::runtime_error("field '" + name + "' has another shape than the case's (" + std::to_string(count) +
                               " x " + std::to_string(components) + ")");
    if (count > 0 && H5Dread(data.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values) < 0)
      throw std::runtime_error("cannot read field '" + name + "'");
  };
  for (const std::string& name : fields.names()) {
    if (!fields.allocated(name)) continue;
    const FieldInfo& info = fields.info(name);
    if (info.type == FieldType::Int64) read(name, info.components, H5T_NATIVE_INT64, fields.i64(name));
    else read(name, info.components, H5T_NATIVE_DOUBLE, fields.f64(name));
  }
  for (ParticleArray& e : extra) {
    e.values.assign(count * static_cast<std::size_t>(e.components), 0.0);
    read(e.name, e.components, H5T_NATIVE_DOUBLE, e.values.data());
  }
  Handle data{check(H5Dopen2(f.id, "state", H5P_DEFAULT), "open dataset state"), H5Dclose};
  Handle space{check(H5Dget_space(data.id), "read the shape of state"), H5Sclose};
  hsize_t length = 0;
  H5Sget_simple_extent_dims(space.id, &length, nullptr);
  std::string state(length, '\0');
  if (length > 0 && H5Dread(data.id, H5T_NATIVE_CHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, state.data()) < 0)
    throw std::runtime_error("cannot read the run state");
  return state;
}

}  // namespace sphforge::io
