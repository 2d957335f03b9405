// The HDF5 particle dump written when a run becomes unstable: every allocated field comes back
// with its values, shape and unit, and the root carries time and step.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "io/particle_dump.hpp"

namespace {

using namespace sphforge;
namespace fs = std::filesystem;

TEST(ParticleDump, EveryFieldRoundTripsWithShapeAndUnit) {
  FieldRegistry fields;
  fields.declare({field::position, 3, "m"}, "test");
  fields.declare({field::id, 1, "1", FieldType::Int64}, "test");
  fields.allocate(4);
  for (int i = 0; i < 12; ++i) fields.f64(field::position)[i] = 0.1 * i + 1e-17;
  for (int i = 0; i < 4; ++i) fields.i64(field::id)[i] = 100 + i;
  const fs::path file = fs::temp_directory_path() / ("sphforge_dump_" + std::to_string(::getpid()) + ".h5");
  // An array held outside the registry (the friction memory, expanded per particle) is dumped too.
  io::ParticleArray extra{"friction_history_die", 3, "N", std::vector<double>(12, 0.0)};
  extra.values[3 * 2 + 1] = -0.75;
  io::write_particle_dump(file, fields, 4, 0.25, 17, {extra});

  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  double time = 0.0;
  long long step = 0;
  hid_t a = H5Aopen(f, "time_s", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &time);
  H5Aclose(a);
  a = H5Aopen(f, "step", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_LLONG, &step);
  H5Aclose(a);
  EXPECT_EQ(time, 0.25);
  EXPECT_EQ(step, 17);

  const hid_t d = H5Dopen2(f, "/fields/position", H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t space = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  EXPECT_EQ(H5Sget_simple_extent_ndims(space), 2);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  EXPECT_EQ(dims[0], 4u);
  EXPECT_EQ(dims[1], 3u);
  std::vector<double> x(12);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data());
  for (int i = 0; i < 12; ++i) EXPECT_EQ(x[i], 0.1 * i + 1e-17);  // full precision
  const hid_t unit = H5Aopen(d, "unit", H5P_DEFAULT);
  const hid_t type = H5Aget_type(unit);
  std::string text(H5Tget_size(type), '\0');
  H5Aread(unit, type, text.data());
  EXPECT_STREQ(text.c_str(), "m");
  H5Tclose(type);
  H5Aclose(unit);
  H5Sclose(space);
  H5Dclose(d);

  const hid_t ids = H5Dopen2(f, "/fields/id", H5P_DEFAULT);
  ASSERT_GE(ids, 0);
  std::vector<long long> id(4);
  H5Dread(ids, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, id.data());
  EXPECT_EQ(id[3], 103);
  H5Dclose(ids);
  const hid_t hist = H5Dopen2(f, "/fields/friction_history_die", H5P_DEFAULT);
  ASSERT_GE(hist, 0);
  std::vector<double> h(12, 1.0);
  H5Dread(hist, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, h.data());
  EXPECT_EQ(h[7], -0.75);
  EXPECT_EQ(h[6], 0.0);
  H5Dclose(hist);
  H5Fclose(f);
  fs::remove(file);
}

}  // namespace
