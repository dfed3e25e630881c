// The background grid: a regular lattice of cubic cells covering the scene's domain, with
// node fields stored as structure of arrays (m_i, mv_i, f_i, v_i).
//
// Node lattice indices run from -kGhost to cells[d] + kGhost in each direction: the domain
// box [origin, origin + cells h] has nodes 0..cells[d]; one ghost layer outside each face
// lets every point inside the closed domain box use a full stencil (linear and quadratic
// B-spline), so stencil indices never leave the arrays. Walls act on the boundary nodes and
// on the ghost layer behind them.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "scene.hpp"
#include "shape_functions.hpp"

namespace mpmdem::mpm {

struct Grid {
  static constexpr int kGhost = 1;

  explicit Grid(const GridParams& params);

  Vec3 origin = Vec3::Zero();
  double h = 1.0;                       // cell size [m]
  double inv_h = 1.0;                   // 1 / h
  std::array<int, 3> cells{{0, 0, 0}};  // cells per direction (extent rounded up)
  std::array<int, 3> nodes{{0, 0, 0}};  // nodes per direction, ghosts included
  // Nodes with m_i <= mass_floor are empty (v_i = 0). The solver sets a tiny fraction of the
  // smallest point mass, so that round-off masses never divide a force.
  double mass_floor = 0.0;
  // The axes as the shape functions see them (cells, clamped quadratic B-splines at walls:
  // the solver sets the clamps from the scene's walls).
  std::array<ShapeAxis, 3> axes{};

  // Node fields (index(i, j, k)).
  std::vector<double> m_i;    // mass [kg]
  std::vector<Vec3> mv_i;     // momentum [kg m/s]
  std::vector<Vec3> f_i;      // internal force, then total force [N]
  std::vector<Vec3> v_i;      // velocity after the grid update (v_i^{n+1}) [m/s]
  std::vector<Vec3> v0_i;     // velocity before the update (v_i^n = mv_i / m_i) [m/s]
  std::vector<Vec3> vstar_i;  // XPIC only: v* from v0_i (xpic.hpp) [m/s]

  std::size_t size() const { return m_i.size(); }
  // Flat index of lattice node (i, j, k), each in [-kGhost, cells + kGhost]; i fastest.
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i + kGhost) +
           static_cast<std::size_t>(nodes[0]) *
               (static_cast<std::size_t>(j + kGhost) +
                static_cast<std::size_t>(nodes[1]) * static_cast<std::size_t>(k + kGhost));
  }
  // Lattice index of a flat index.
  std::array<int, 3> lattice(std::size_t idx) const;
  Vec3 position(int i, int j, int k) const { return origin + h * Vec3(i, j, k); }
  Vec3 upper() const { return origin + h * Vec3(cells[0], cells[1], cells[2]); }
  // Is x inside the closed domain box (false for NaN)? Only such points may be transferred.
  bool contains(const Vec3& x) const;

  // m_i = 0, mv_i = 0, f_i = 0 (v_i and v0_i are written by the grid update).
  void clear();
};

}  // namespace mpmdem::mpm
