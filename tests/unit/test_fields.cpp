// FieldRegistry: declaration, allocation, shape checks, typed access, permutation, memory.
#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphforge/fields.hpp"

using namespace sphforge;

namespace {

FieldInfo f64_field(const std::string& name, int comps, const std::string& unit = "1") {
  return FieldInfo{name, comps, unit, FieldType::Float64, true};
}

FieldInfo i64_field(const std::string& name) { return FieldInfo{name, 1, "1", FieldType::Int64, true}; }

// Expects `fn` to throw std::logic_error whose message mentions `needle`.
template <typename Fn>
void expect_logic_error_naming(Fn&& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "expected std::logic_error mentioning '" << needle << "'";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(FieldRegistry, UndeclaredFieldIsNotAllocated) {
  FieldRegistry reg;
  reg.declare(f64_field(field::position, 3, "m"), "core");
  reg.declare(f64_field(field::velocity, 3, "m/s"), "core");
  reg.allocate(5);

  EXPECT_EQ(reg.size(), 5u);
  EXPECT_TRUE(reg.allocated(field::position));
  EXPECT_FALSE(reg.declared(field::temperature));
  EXPECT_FALSE(reg.allocated(field::temperature));
  EXPECT_EQ(reg.f64_if(field::temperature), nullptr);
  EXPECT_NE(reg.f64_if(field::velocity), nullptr);
  expect_logic_error_naming([&] { reg.f64(field::temperature); }, "temperature");
  EXPECT_EQ(reg.names(), (std::vector<std::string>{"position", "velocity"}));
}

TEST(FieldRegistry, AllocateZeroFillsAndResizeKeepsData) {
  FieldRegistry reg;
  reg.declare(f64_field(field::velocity, 3), "a");
  reg.declare(i64_field(field::id), "a");
  reg.allocate(4);
  double* v = reg.f64(field::velocity);
  std::int64_t* id = reg.i64(field::id);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(v[i], 0.0);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(id[i], 0);
  for (int i = 0; i < 12; ++i) v[i] = 1.5 * i;
  for (int i = 0; i < 4; ++i) id[i] = 100 + i;

  reg.resize(6);
  EXPECT_EQ(reg.size(), 6u);
  v = reg.f64(field::velocity);
  id = reg.i64(field::id);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(v[i], 1.5 * i);
  for (int i = 12; i < 18; ++i) EXPECT_EQ(v[i], 0.0);
  EXPECT_EQ(id[3], 103);
  EXPECT_EQ(id[5], 0);

  reg.allocate(2);  // allocate starts over: zero-filled
  EXPECT_EQ(reg.f64(field::velocity)[0 + 3], 0.0);
}

TEST(FieldRegistry, RedeclareSameShapeAddsUser) {
  FieldRegistry reg;
  reg.declare(f64_field(field::pressure, 1), "eos", Access::Write);
  reg.declare(f64_field(field::pressure, 1, "Pa"), "momentum", Access::Read);
  reg.declare(f64_field(field::pressure, 1), "eos", Access::Write);  // no duplicate user
  EXPECT_EQ(reg.declared_by(field::pressure), (std::vector<std::string>{"eos", "momentum"}));
  // The specific unit wins over the default "1" whatever the order of declaration.
  EXPECT_EQ(reg.info(field::pressure).unit, "Pa");
  EXPECT_EQ(reg.names().size(), 1u);
}

TEST(FieldRegistry, ShapeMismatchThrows) {
  FieldRegistry reg;
  reg.declare(f64_field(field::deviatoric_stress, 6), "stress");
  expect_logic_error_naming([&] { reg.declare(f64_field(field::deviatoric_stress, 9), "other"); },
                            "deviatoric_stress");
  FieldInfo wrong_type = f64_field(field::deviatoric_stress, 6);
  wrong_type.type = FieldType::Int64;
  expect_logic_error_naming([&] { reg.declare(wrong_type, "other"); }, "deviatoric_stress");
  // The failed declarations changed nothing.
  EXPECT_EQ(reg.info(field::deviatoric_stress).components, 6);
  EXPECT_EQ(reg.declared_by(field::deviatoric_stress), (std::vector<std::string>{"stress"}));
}

TEST(FieldRegistry, WrongTypeOrUnallocatedAccessThrows) {
  FieldRegistry reg;
  reg.declare(f64_field(field::mass, 1), "core");
  reg.declare(i64_field(field::body), "core");
  expect_logic_error_naming([&] { reg.f64(field::mass); }, "mass");  // not yet allocated
  reg.allocate(3);
  expect_logic_error_naming([&] { reg.i64(field::mass); }, "mass");
  expect_logic_error_naming([&] { reg.f64(field::body); }, "body");

  // Declared after allocate(): not allocated until the next allocate/resize.
  reg.declare(f64_field(field::temperature, 1, "K"), "thermal");
  EXPECT_TRUE(reg.declared(field::temperature));
  EXPECT_FALSE(reg.allocated(field::temperature));
  expect_logic_error_naming([&] { reg.f64(field::temperature); }, "temperature");
  reg.resize(3);
  ASSERT_TRUE(reg.allocated(field::temperature));
  EXPECT_EQ(reg.f64(field::temperature)[2], 0.0);
}

TEST(FieldRegistry, PermuteReordersEveryComponentOfEveryField) {
  FieldRegistry reg;
  reg.declare(f64_field(field::position, 3), "core");
  reg.declare(f64_field(field::pressure, 1), "core");
  reg.declare(i64_field(field::id), "core");
  reg.allocate(4);
  double* x = reg.f64(field::position);
  double* p = reg.f64(field::pressure);
  std::int64_t* id = reg.i64(field::id);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) x[3 * i + c] = 10.0 * i + c;
    p[i] = 0.5 * i;
    id[i] = 7 + i;
  }

  const std::array<std::size_t, 4> order{2, 0, 3, 1};
  reg.permute(order);
  x = reg.f64(field::position);
  p = reg.f64(field::pressure);
  id = reg.i64(field::id);
  for (int i = 0; i < 4; ++i) {
    const double old = static_cast<double>(order[i]);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(x[3 * i + c], 10.0 * old + c) << i << "," << c;
    EXPECT_EQ(p[i], 0.5 * old);
    EXPECT_EQ(id[i], 7 + static_cast<std::int64_t>(order[i]));
  }

  const std::array<std::size_t, 3> short_order{0, 1, 2};
  EXPECT_THROW(reg.permute(short_order), std::logic_error);
  const std::array<std::size_t, 4> out_of_range{0, 1, 2, 4};
  EXPECT_THROW(reg.permute(out_of_range), std::logic_error);
  EXPECT_EQ(reg.i64(field::id)[0], 9);  // unchanged by the rejected permutations
}

TEST(FieldRegistry, BytesCountsAllocatedArraysOnly) {
  FieldRegistry reg;
  reg.declare(f64_field(field::position, 3), "core");
  reg.declare(f64_field(field::velocity_gradient, 9), "core");
  reg.declare(i64_field(field::id), "core");
  EXPECT_EQ(reg.bytes(), 0u);
  reg.allocate(10);
  EXPECT_EQ(reg.bytes(), (10u * 3 + 10u * 9) * sizeof(double) + 10u * sizeof(std::int64_t));

  // Permuting must not move memory between fields of different sizes.
  std::vector<std::size_t> order(10);
  for (std::size_t i = 0; i < 10; ++i) order[i] = 9 - i;
  reg.permute(order);
  EXPECT_EQ(reg.bytes(), (10u * 3 + 10u * 9) * sizeof(double) + 10u * sizeof(std::int64_t));
}
