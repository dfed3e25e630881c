// Boundary conditions on grid node velocities: walls on the six faces of the domain box and
// velocity constraints on boxes (or planes) of nodes that hold until released.
//
// Walls act on the nodes of the boundary plane and on the ghost layer behind it:
//   fixed    v = 0 (no-slip, the "rough" base);
//   slip     normal component 0 (frictionless);
//   friction unilateral contact with Coulomb friction: a node moving into the wall loses its
//            normal component v_n and its tangential speed is reduced by mu v_n, never
//            reversed; a node moving away is free;
//   free     nothing.
// With quadratic B-splines the splines are clamped at every wall (shape_functions.hpp): only
// the ghost slot's function is non-zero on the wall, so the wall acts on the ghost layer alone
// and the boundary node's slot (centred h/4 inside) stays free. (Linear stencils never reach
// the ghost layer.)
// Faces are applied in the order x_min, x_max, y_min, y_max, z_min, z_max, then the active
// velocity constraints (their held components are set to the value).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "grid.hpp"
#include "scene.hpp"

namespace mpmdem::mpm {

// Are the quadratic B-splines clamped at face f (x_min, x_max, y_min, ...)? At every wall when
// the scene uses them.
bool clamped_face(const Scene& scene, int f);
// Sets grid.axes' clamps from the scene's walls and shape functions.
void set_shape_axes(const Scene& scene, Grid& grid);

class BoundaryConditions {
 public:
  BoundaryConditions(const Scene& scene, const Grid& grid);

  // Apply walls, then the active velocity constraints, to a node velocity field.
  void apply(std::vector<Vec3>& v_i) const;

  // After a step: release constraints whose time has come (time >= release_time) or whose
  // condition holds (time >= release_min_time and E_k < release_kinetic_ratio |E_p0|).
  // Appends one human-readable event per release.
  void update_releases(double time, double E_k, double E_p0, std::vector<std::string>& events);

  std::size_t constraint_count() const { return constraints_.size(); }
  bool constraint_active(std::size_t c) const { return constraints_[c].active; }
  void set_active(std::size_t c, bool active) { constraints_.at(c).active = active; }
  const std::vector<std::size_t>& constraint_nodes(std::size_t c) const {
    return constraints_[c].nodes;
  }
  // Is any constraint waiting for the kinetic-energy condition (the solver then needs E_k)?
  bool needs_kinetic_energy() const;

 private:
  struct Face {
    WallType type = WallType::kFree;
    double mu = 0.0;
    int axis = 0;
    double outward = 1.0;            // -1 on a min face, +1 on a max face
    std::vector<std::size_t> nodes;  // boundary plane and ghost layer (linear), ghosts (clamped)
  };
  struct Constraint {
    VelocityConstraintParams params;
    std::vector<std::size_t> nodes;
    bool active = true;
  };
  std::vector<Face> faces_;
  std::vector<Constraint> constraints_;
};

}  // namespace mpmdem::mpm
