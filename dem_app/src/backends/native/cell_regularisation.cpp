// Flip and tiling of the periodic cell: see cell_regularisation.hpp.
#include "backends/native/cell_regularisation.hpp"

#include <Eigen/LU>
#include <algorithm>

namespace mpmdem::dem::native {

bool flip_cell(RveState& s, NeighbourList& nl) {
  const Eigen::Matrix3i m = s.cell.flip();
  if (m == Eigen::Matrix3i::Identity()) return false;
  // hsize_new = hsize_old M: the image H_old c is H_new M^-1 c (M is unimodular).
  const Eigen::Matrix3d inv = m.cast<double>().inverse();
  auto& cells = s.contacts.cell;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const Eigen::Vector3d v = inv * cells[k].cast<double>();
    cells.set(k, to_cell_dist(Eigen::Vector3i(static_cast<int>(std::lround(v[0])),
                                              static_cast<int>(std::lround(v[1])),
                                              static_cast<int>(std::lround(v[2])))));
  }
  nl.invalidate();
  return true;
}

int tile_if_thin(RveState& s, NeighbourList& nl) {
  auto& sp = s.spheres;
  if (sp.size() == 0) return -1;
  const Eigen::Vector3d h = s.cell.heights();
  int i = 0;
  for (int a = 1; a < 3; ++a)
    if (h[a] < h[i]) i = a;
  const double d_max = 2.0 * *std::max_element(sp.radius.begin(), sp.radius.end());
  if (h[i] >= kTileHeight * d_max) return -1;
  const Vec3 shift = s.cell.hsize.col(i);
  const Eigen::Matrix3d& l = s.cell.vel_grad;  // O.cell.velGrad in mpmdem_rve.py
  const std::size_t n = sp.size();
  sp.resize(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t c = n + k;
    sp.radius[c] = sp.radius[k];
    sp.mass[c] = sp.mass[k];
    sp.inertia[c] = sp.inertia[k];
    sp.pos.set(c, sp.pos[k] + shift);
    sp.vel.set(c, sp.vel[k] + l * shift);
    sp.ang_vel.set(c, sp.ang_vel[k]);
    sp.ori[c] = sp.ori[k];
    sp.ref_ori[c] = sp.ref_ori[k];
  }
  s.contacts.clear();
  s.cell.hsize.col(i) *= 2.0;
  nl.invalidate();
  return i;
}

}  // namespace mpmdem::dem::native
