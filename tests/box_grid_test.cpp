// BoxGrid: every box a query may meet comes back, in ascending order, whatever the boxes' sizes
// and wherever the query lies, and a query far from most boxes gets few of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "physics/box_grid.hpp"

namespace sear {
namespace {

using Box = std::array<double, 6>;

bool meet(const Box& a, const double* b, double margin) {
  return !(a[0] > b[1] + margin || a[1] < b[0] - margin || a[2] > b[3] + margin || a[3] < b[2] - margin ||
           a[4] > b[5] + margin || a[5] < b[4] - margin);
}

Box random_box(std::mt19937& random, double spread, double size) {
  std::uniform_real_distribution<double> at(-spread, spread), extent(0.01, size);
  const double x = at(random), y = at(random), z = at(random) / 10;
  const double dx = extent(random), dy = extent(random), dz = extent(random);
  return {x - dx, x + dx, y - dy, y + dy, z - dz, z + dz};
}

// 500 boxes over 40 m, a plane, a slab over more cells than a box may hold, a wall, and one box
// far out: 2 km (a big field), or 10 000 km (nonsense, where the cells grow to 96 m and the search
// degrades to testing most boxes, but loses none).
std::size_t check_queries(double far_out_m) {
  std::mt19937 random(7);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Box> boxes;
  for (int i = 0; i < 500; ++i) boxes.push_back(random_box(random, 20, 1.5));
  boxes.push_back({-inf, inf, -inf, inf, -inf, 0});
  boxes.push_back({-30, 30, -30, 30, -1, 0.2});
  boxes.push_back({-20, 20, 14.9, 15.1, 0, 0.6});
  boxes.push_back({far_out_m, far_out_m + 1, 0, 1, 0, 1});
  const BoxGrid grid(boxes);
  std::size_t returned = 0, met = 0;
  for (int q = 0; q < 2000; ++q) {
    Box query = random_box(random, 25, q % 10 == 0 ? 8 : 0.4);
    const double margin = q % 3 == 0 ? 0.05 : 0;
    const std::vector<std::uint32_t>& near = grid.near(query.data(), margin);
    EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
    EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end()) << "a box twice";
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (meet(boxes[i], query.data(), margin)) {
        ++met;
        EXPECT_TRUE(std::binary_search(near.begin(), near.end(), i)) << "query " << q << " lost box " << i;
      }
    returned += near.size();
  }
  EXPECT_GT(met, 2000u);  // the queries do meet boxes: what is checked above is not empty
  return returned / 2000;
}

TEST(BoxGrid, EveryBoxAQueryMeetsComesBackInOrder) {
  // Cells of 1.35 m, a few boxes in each: a query gets the two kept apart and those of the one
  // to four cells it touches (6 of the 504 on average, one query in ten being 8 m wide); testing
  // them all would be 504.
  EXPECT_LT(check_queries(2000), 20u);
  check_queries(1e7);
}

TEST(BoxGrid, CellsOfAMetreReturnOnlyWhatIsNear) {
  std::vector<Box> boxes;
  for (int i = 0; i < 400; ++i) {
    const double x = i % 20 * 2.0, y = i / 20 * 2.0;  // 0.5 m boxes every 2 m over 40 m
    boxes.push_back({x, x + 0.5, y, y + 0.5, 0, 0.5});
  }
  const BoxGrid grid(boxes);
  // A 0.3 m robot between four boxes touches cells holding at most those four.
  const double robot[6] = {10.6, 10.9, 10.6, 10.9, 0, 0.2};
  EXPECT_LE(grid.near(robot).size(), 4u);
  const double on_one[6] = {10.2, 10.4, 10.2, 10.4, 0, 0.2};
  const std::vector<std::uint32_t>& near = grid.near(on_one);
  EXPECT_NE(std::find(near.begin(), near.end(), 5u * 20u + 5u), near.end());
}

// Boxes strung along a line 1000 km long: the grid stays within its cells (a line of them), and
// still finds each box.
TEST(BoxGrid, BoxesAlongALongLineStillFound) {
  std::vector<Box> boxes;
  for (int i = 0; i <= 100; ++i) boxes.push_back({i * 1e4, i * 1e4 + 1, 0, 0.5, 0, 1});
  const BoxGrid grid(boxes);
  EXPECT_LE(grid.cell_count(), 3u * 65536u + 1u);  // cells over 0.5 m x 1000 km at the least area
  for (int i = 0; i <= 100; ++i) {
    const double query[6] = {i * 1e4 + 0.5, i * 1e4 + 0.6, 0.2, 0.3, 0, 1};
    const std::vector<std::uint32_t>& near = grid.near(query);
    EXPECT_TRUE(std::binary_search(near.begin(), near.end(), static_cast<std::uint32_t>(i)));
    EXPECT_LE(near.size(), 2u);  // cells of 15 m, boxes 10 km apart
  }
}

TEST(BoxGrid, UnboundedOrNaNQueriesGetEverything) {
  std::vector<Box> boxes;
  for (int i = 0; i < 50; ++i) boxes.push_back({i * 1.0, i + 0.5, 0, 0.5, 0, 0.5});
  const BoxGrid grid(boxes);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double with_nan[6] = {nan, 1, 0, 1, 0, 1};
  const double endless[6] = {-inf, inf, 0, 1, 0, 1};
  EXPECT_EQ(grid.near(with_nan).size(), 50u);
  EXPECT_EQ(grid.near(endless).size(), 50u);
  const double far_off[6] = {500, 501, 500, 501, 0, 1};
  EXPECT_TRUE(grid.near(far_off).empty());
}

}  // namespace
}  // namespace sear
