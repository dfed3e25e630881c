#include "grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mpmdem::mpm {

Grid::Grid(const GridParams& params) : origin(params.origin), h(params.cell_size) {
  if (!(h > 0.0) || !std::isfinite(h)) {
    throw std::invalid_argument("grid.cell_size must be positive and finite");
  }
  inv_h = 1.0 / h;
  for (int d = 0; d < 3; ++d) {
    // Rounded up to whole cells; an extent within 1e-9 cells of a whole number is that number.
    const double n = params.extent[d] * inv_h;
    cells[d] = std::max(1, static_cast<int>(std::ceil(n - 1e-9)));
    nodes[d] = cells[d] + 1 + 2 * kGhost;
    axes[static_cast<std::size_t>(d)].cells = cells[d];
  }
  const std::size_t n = static_cast<std::size_t>(nodes[0]) * static_cast<std::size_t>(nodes[1]) *
                        static_cast<std::size_t>(nodes[2]);
  m_i.assign(n, 0.0);
  mv_i.assign(n, Vec3::Zero());
  f_i.assign(n, Vec3::Zero());
  v_i.assign(n, Vec3::Zero());
  v0_i.assign(n, Vec3::Zero());
}

std::array<int, 3> Grid::lattice(std::size_t idx) const {
  const auto nx = static_cast<std::size_t>(nodes[0]);
  const auto ny = static_cast<std::size_t>(nodes[1]);
  return {{static_cast<int>(idx % nx) - kGhost, static_cast<int>((idx / nx) % ny) - kGhost,
           static_cast<int>(idx / (nx * ny)) - kGhost}};
}

bool Grid::contains(const Vec3& x) const {
  const Vec3 hi = upper();
  for (int d = 0; d < 3; ++d) {
    if (!(x[d] >= origin[d] && x[d] <= hi[d])) return false;
  }
  return true;
}

void Grid::clear() {
  std::fill(m_i.begin(), m_i.end(), 0.0);
  std::fill(mv_i.begin(), mv_i.end(), Vec3::Zero());
  std::fill(f_i.begin(), f_i.end(), Vec3::Zero());
}

}  // namespace mpmdem::mpm
