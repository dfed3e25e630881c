// The periodic cell: see periodic_cell.hpp.
#include "backends/native/periodic_cell.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace mpmdem::dem::native {

Eigen::Vector3d PeriodicCell::heights() const {
  const double vol = std::abs(hsize.determinant());
  Eigen::Vector3d h;
  for (int i = 0; i < 3; ++i) {
    h[i] = vol / hsize.col((i + 1) % 3).cross(hsize.col((i + 2) % 3)).norm();
  }
  return h;
}

Eigen::Matrix3i PeriodicCell::flip() {
  Eigen::Matrix3d h = hsize;
  Eigen::Matrix3i total = Eigen::Matrix3i::Identity();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    Eigen::Matrix3d base = h;
    base.col(i) = h.col(j).cross(h.col(k));
    const Eigen::Vector3d coord = base.inverse() * h.col(i);
    Eigen::Matrix3i step = Eigen::Matrix3i::Zero();
    step(j, i) = -static_cast<int>(std::floor(coord[j] + 0.5));
    step(k, i) = -static_cast<int>(std::floor(coord[k] + 0.5));
    h += h * step.cast<double>();
    total += total * step;
  }
  if (total != Eigen::Matrix3i::Identity()) hsize = h;
  return total;
}

}  // namespace mpmdem::dem::native
