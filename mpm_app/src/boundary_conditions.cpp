#include "boundary_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mpmdem::mpm {

bool clamped_face(const Scene& scene, int f) {
  return scene.solver.shape == ShapeKind::kQuadraticBSpline &&
         scene.walls[static_cast<std::size_t>(f)].type != WallType::kFree;
}

void set_shape_axes(const Scene& scene, Grid& grid) {
  for (std::size_t d = 0; d < 3; ++d) {
    grid.axes[d].clamp_lo = clamped_face(scene, static_cast<int>(2 * d));
    grid.axes[d].clamp_hi = clamped_face(scene, static_cast<int>(2 * d + 1));
  }
}

BoundaryConditions::BoundaryConditions(const Scene& scene, const Grid& grid) {
  for (int f = 0; f < 6; ++f) {
    const WallParams& w = scene.walls[static_cast<std::size_t>(f)];
    if (w.type == WallType::kFree) continue;
    Face face;
    face.type = w.type;
    face.mu = w.friction;
    face.axis = f / 2;
    face.outward = f % 2 == 0 ? -1.0 : 1.0;
    const int n = grid.cells[static_cast<std::size_t>(face.axis)];
    const bool clamped = clamped_face(scene, f);
    for (std::size_t i = 0; i < grid.size(); ++i) {
      const int k = grid.lattice(i)[static_cast<std::size_t>(face.axis)];
      const bool ghost = face.outward < 0.0 ? k == -1 : k == n + 1;
      const bool behind = face.outward < 0.0 ? k <= 0 : k >= n;
      // A single cell between two clamped walls is a plane-strain slice: its two interior
      // functions would be controlled by one point across, so the wall holds them too.
      if (clamped && n > 1 ? ghost : behind) face.nodes.push_back(i);
    }
    faces_.push_back(std::move(face));
  }
  const double tol = 1e-9 * grid.h;
  for (const VelocityConstraintParams& c : scene.constraints) {
    Constraint con;
    con.params = c;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      const auto l = grid.lattice(i);
      const Vec3 x = grid.position(l[0], l[1], l[2]);
      if ((x.array() >= c.min.array() - tol).all() && (x.array() <= c.max.array() + tol).all()) {
        con.nodes.push_back(i);
      }
    }
    constraints_.push_back(std::move(con));
  }
}

void BoundaryConditions::apply(std::vector<Vec3>& v_i) const {
  for (const Face& face : faces_) {
    const int a = face.axis;
    switch (face.type) {
      case WallType::kFixed:
        for (std::size_t i : face.nodes) v_i[i].setZero();
        break;
      case WallType::kSlip:
        for (std::size_t i : face.nodes) v_i[i][a] = 0.0;
        break;
      case WallType::kFriction:
        for (std::size_t i : face.nodes) {
          Vec3& v = v_i[i];
          const double v_n = face.outward * v[a];  // > 0: moving into the wall
          if (v_n <= 0.0) continue;
          v[a] = 0.0;
          const double v_t = v.norm();
          if (v_t > 0.0) v *= std::max(0.0, 1.0 - face.mu * v_n / v_t);
        }
        break;
      case WallType::kFree:
        break;
    }
  }
  for (const Constraint& c : constraints_) {
    if (!c.active) continue;
    for (std::size_t i : c.nodes) {
      for (int d = 0; d < 3; ++d) {
        if (c.params.components[static_cast<std::size_t>(d)]) v_i[i][d] = c.params.value[d];
      }
    }
  }
}

bool BoundaryConditions::needs_kinetic_energy() const {
  for (const Constraint& c : constraints_) {
    if (c.active && c.params.release_kinetic_ratio) return true;
  }
  return false;
}

void BoundaryConditions::update_releases(double time, double E_k, double E_p0,
                                         std::vector<std::string>& events) {
  for (Constraint& c : constraints_) {
    if (!c.active) continue;
    const VelocityConstraintParams& p = c.params;
    std::ostringstream why;
    if (p.release_time && time >= *p.release_time * (1.0 - 1e-12)) {
      why << "release_time " << *p.release_time << " s reached";
    } else if (p.release_kinetic_ratio && time >= p.release_min_time &&
               E_k < *p.release_kinetic_ratio * std::abs(E_p0)) {
      why << "E_k/E_p0=" << (E_p0 != 0.0 ? E_k / std::abs(E_p0) : 0.0) << " < "
          << *p.release_kinetic_ratio;
    } else {
      continue;
    }
    c.active = false;
    std::ostringstream msg;
    msg << "constraint '" << p.name << "' released at t=" << time << " s (" << why.str() << ")";
    events.push_back(msg.str());
  }
}

}  // namespace mpmdem::mpm
