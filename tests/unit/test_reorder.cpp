// Locality reordering (engine/reorder.hpp): a permutation that keeps every particle inside its
// body's index range, sorts each range by the Morton code of the cell, is deterministic, and moves
// every registered field consistently.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "engine/reorder.hpp"

using namespace sphforge;

TEST(Reorder, MortonCodeInterleavesBits) {
  EXPECT_EQ(morton_code(0, 0, 0), 0u);
  EXPECT_EQ(morton_code(1, 0, 0), 1u);
  EXPECT_EQ(morton_code(0, 1, 0), 2u);
  EXPECT_EQ(morton_code(0, 0, 1), 4u);
  EXPECT_EQ(morton_code(2, 0, 0), 8u);
  EXPECT_EQ(morton_code(3, 3, 3), 63u);
}

TEST(Reorder, PermutesWithinBodiesAndMovesEveryField) {
  // Two bodies of scattered particles; the second body's range is [300, 500).
  const std::size_t n = 500;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  FieldRegistry fields;
  fields.declare({field::position, 3, "m"}, "test");
  fields.declare({field::id, 1, "1", FieldType::Int64}, "test");
  fields.declare({field::body, 1, "1", FieldType::Int64}, "test");
  fields.declare({field::deviatoric_stress, 6, "Pa"}, "test");
  fields.allocate(n);
  double* x = fields.f64(field::position);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) x[3 * i + d] = u(rng);
    fields.i64(field::id)[i] = static_cast<std::int64_t>(i);
    fields.i64(field::body)[i] = i < 300 ? 0 : 1;
    for (int c = 0; c < 6; ++c) fields.f64(field::deviatoric_stress)[6 * i + c] = 10.0 * i + c;
  }
  for (int d = 0; d < 3; ++d) x[d] = 0.0;  // so that the bounding box starts at the origin
  const std::vector<double> x0(x, x + 3 * n);
  const std::vector<BodyRange> bodies = {{"a", 0, 300, 0.1}, {"b", 300, 200, 0.1}};

  std::vector<std::size_t> order, again;
  morton_order(x, n, 0.1, bodies, order);
  morton_order(x, n, 0.1, bodies, again);
  EXPECT_EQ(order, again);  // deterministic
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i);  // a permutation
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(order[i] < 300, i < 300) << i;  // within its body

  ASSERT_TRUE(reorder_by_cell(fields, bodies, 0.1));
  const auto cell_key = [&](const double* p) {
    return morton_code(static_cast<std::uint32_t>(p[0] / 0.1), static_cast<std::uint32_t>(p[1] / 0.1),
                       static_cast<std::uint32_t>(p[2] / 0.1));
  };
  x = fields.f64(field::position);
  for (std::size_t i = 0; i < n; ++i) {
    const auto id = static_cast<std::size_t>(fields.i64(field::id)[i]);
    EXPECT_EQ(fields.i64(field::body)[i], i < 300 ? 0 : 1);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(x[3 * i + d], x0[3 * id + d]);
    EXPECT_EQ(fields.f64(field::deviatoric_stress)[6 * i + 5], 10.0 * id + 5);
    if (i + 1 != 300 && i + 1 < n) {  // sorted by cell inside each body
      const auto next = static_cast<std::size_t>(fields.i64(field::id)[i + 1]);
      EXPECT_TRUE(cell_key(x + 3 * i) < cell_key(x + 3 * i + 3) ||
                  (cell_key(x + 3 * i) == cell_key(x + 3 * i + 3) && id < next))
          << i;
    }
  }
  // Already sorted: nothing to do.
  EXPECT_FALSE(reorder_by_cell(fields, bodies, 0.1));
}
