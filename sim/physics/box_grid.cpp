#include "physics/box_grid.hpp"

#include <algorithm>
#include <cmath>

namespace sear {
namespace {

constexpr double kMinCellM = 1.0;  // a robot's box touches one to four cells
constexpr double kMaxGridCells = 65536;
constexpr std::int64_t kMaxCells = 1024;

bool bounded(const std::array<double, 6>& b) {
  return std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && std::isfinite(b[3]);
}

}  // namespace

BoxGrid::BoxGrid(const std::vector<std::array<double, 6>>& boxes) : count_(boxes.size()) {
  for (std::uint32_t i = 0; i < boxes.size(); ++i) all_.push_back(i);
  stamp_.assign(boxes.size(), 0);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const auto& b : boxes) {
    if (!bounded(b)) continue;
    lo[0] = std::min(lo[0], b[0]), hi[0] = std::max(hi[0], b[1]);
    lo[1] = std::min(lo[1], b[2]), hi[1] = std::max(hi[1], b[3]);
  }
  if (!(lo[0] <= hi[0] && lo[1] <= hi[1])) lo[0] = hi[0] = lo[1] = hi[1] = 0;
  // At most kMaxGridCells along either side, and about as many (three times at worst) in all.
  const double width = hi[0] - lo[0], depth = hi[1] - lo[1];
  cell_m_ = std::max({kMinCellM, std::sqrt(width * depth / kMaxGridCells), width / kMaxGridCells, depth / kMaxGridCells});
  x0_ = lo[0], y0_ = lo[1];
  columns_ = static_cast<std::int64_t>(std::floor((hi[0] - lo[0]) / cell_m_)) + 1;
  rows_ = static_cast<std::int64_t>(std::floor((hi[1] - lo[1]) / cell_m_)) + 1;
  cells_.assign(static_cast<std::size_t>(columns_ * rows_), {});
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    const auto& b = boxes[i];
    const double box_lo[2] = {b[0], b[2]}, box_hi[2] = {b[1], b[3]};
    Cells c;
    if (!bounded(b) || cells_of(box_lo, box_hi, c) != Reach::Cells) {
      everywhere_.push_back(i);
      continue;
    }
    for (std::int64_t y = c.y0; y <= c.y1; ++y)
      for (std::int64_t x = c.x0; x <= c.x1; ++x) cells_[static_cast<std::size_t>(y * columns_ + x)].push_back(i);
  }
}

BoxGrid::Reach BoxGrid::cells_of(const double lo[2], const double hi[2], Cells& out) const {
  if (!std::isfinite(lo[0]) || !std::isfinite(lo[1]) || !std::isfinite(hi[0]) || !std::isfinite(hi[1]))
    return Reach::Unbounded;
  // Floor is monotonic, so two boxes that meet share the cell of a point they both hold.
  const double x0 = std::floor((lo[0] - x0_) / cell_m_), x1 = std::floor((hi[0] - x0_) / cell_m_);
  const double y0 = std::floor((lo[1] - y0_) / cell_m_), y1 = std::floor((hi[1] - y0_) / cell_m_);
  if (!(x0 <= x1 && y0 <= y1)) return Reach::Unbounded;
  if (x1 < 0 || y1 < 0 || x0 >= static_cast<double>(columns_) || y0 >= static_cast<double>(rows_)) return Reach::Nowhere;
  out = {static_cast<std::int64_t>(std::max(x0, 0.0)), static_cast<std::int64_t>(std::min(x1, static_cast<double>(columns_ - 1))),
         static_cast<std::int64_t>(std::max(y0, 0.0)), static_cast<std::int64_t>(std::min(y1, static_cast<double>(rows_ - 1)))};
  return out.count() <= kMaxCells ? Reach::Cells : Reach::Unbounded;
}

const std::vector<std::uint32_t>& BoxGrid::near(const double box[6], double margin) const {
  const double lo[2] = {box[0] - margin, box[2] - margin}, hi[2] = {box[1] + margin, box[3] + margin};
  Cells c;
  const Reach reach = cells_of(lo, hi, c);
  if (reach == Reach::Unbounded) return all_;
  near_ = everywhere_;
  if (reach == Reach::Nowhere) return near_;
  if (++query_ == 0) {  // wrapped: an old stamp could pass for this query's
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  for (std::int64_t y = c.y0; y <= c.y1; ++y)
    for (std::int64_t x = c.x0; x <= c.x1; ++x)
      for (std::uint32_t i : cells_[static_cast<std::size_t>(y * columns_ + x)]) {
        if (stamp_[i] == query_) continue;
        stamp_[i] = query_;
        near_.push_back(i);
      }
  std::sort(near_.begin(), near_.end());
  return near_;
}

}  // namespace sear
