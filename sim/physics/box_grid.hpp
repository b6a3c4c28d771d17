// Boxes that never move (the scenery's), filed by the cells of the ground plane they cover: which
// of them a box may meet, found without testing them all.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace sear {

// Boxes are {xmin, xmax, ymin, ymax, zmin, zmax}, as ODE's AABBs. Cells are a metre square, or
// larger where the boxes spread over more than 65536 of them. A box unbounded in x or y, or over
// more than 1024 cells (the terrain, a ground slab), is kept apart and returned for every query.
class BoxGrid {
 public:
  explicit BoxGrid(const std::vector<std::array<double, 6>>& boxes = {});

  // The indices, ascending, of every box that `box` grown by `margin` may meet, with some it
  // does not; all of them for a query with NaN or infinite x or y bounds, or over too many cells.
  // Valid until the next call.
  const std::vector<std::uint32_t>& near(const double box[6], double margin = 0) const;
  std::size_t size() const { return count_; }
  std::size_t cell_count() const { return cells_.size(); }  // at most about 3 x 65536

 private:
  struct Cells {
    std::int64_t x0, x1, y0, y1;
    std::int64_t count() const { return (x1 - x0 + 1) * (y1 - y0 + 1); }
  };
  enum class Reach { Cells, Nowhere, Unbounded };  // within the grid; off it; NaN, infinite or too big
  Reach cells_of(const double lo[2], const double hi[2], Cells& out) const;

  std::size_t count_ = 0;
  double x0_ = 0, y0_ = 0, cell_m_ = 1;
  std::int64_t columns_ = 0, rows_ = 0;
  std::vector<std::vector<std::uint32_t>> cells_;  // row-major
  std::vector<std::uint32_t> everywhere_;
  std::vector<std::uint32_t> all_;  // 0, 1, ...
  // Scratch of near(): which query last took each box, and the answer.
  mutable std::vector<std::uint32_t> stamp_;
  mutable std::uint32_t query_ = 0;
  mutable std::vector<std::uint32_t> near_;
};

}  // namespace sear
