// The whole state of one native RVE, as a structure of arrays: one contiguous array per
// field (xyz interleaved within a field), so a step streams through memory and the layout
// maps onto one GPU thread block per RVE later. Nothing here allocates per step.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "backends/native/periodic_cell.hpp"

namespace mpmdem::dem::native {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// FrictMat: the material of every sphere of an RVE (YADE's packings use one).
struct Material {
  double young = 6e8;         // contact modulus E [Pa]
  double ks_kn = 0.8;         // FrictMat.poisson: ks/kn in Ip2_FrictMat_FrictMat_FrictPhys
  double density = 2500;      // [kg/m3]
  double friction_angle = 0;  // [rad]; tan of it caps |Fs|/|Fn|
};

struct Spheres {
  std::vector<double> radius, mass, inertia;  // per sphere [m], [kg], [kg m2]
  std::vector<Vec3> pos, vel, ang_vel;        // unwrapped positions, as YADE keeps them
  std::vector<Quat> ori, ref_ori;             // orientation, and the one rotation counts from
  // Accumulated in a DEM step. Scratch: the backend releases them after each coupling step
  // (release_forces; compute_forces sizes them again), so a resident RVE does not keep them.
  std::vector<Vec3> force, torque;
  std::size_t size() const { return radius.size(); }
  void resize(std::size_t n);
  void push_back(double r, double m, double inertia_value, const Vec3& x);
  std::size_t heap_bytes() const;  // allocated capacity of all arrays
  void release_forces();
};

// Real contacts (Interaction with ScGeom + FrictPhys): body 2's image is pos2 + hsize * cell.
struct Contacts {
  std::vector<std::uint32_t> id1, id2;
  std::vector<Eigen::Vector3i> cell;  // Interaction::cellDist
  std::vector<Vec3> normal;           // ScGeom::normal (unit, 1 -> 2)
  std::vector<Vec3> shear_force;      // FrictPhys::shearForce (rotated with the contact)
  std::vector<double> kn, ks;
  std::vector<double> penetration;  // ScGeom::penetrationDepth (last step)
  std::size_t size() const { return id1.size(); }
  // FrictPhys::normalForce of the last step, recomputed exactly as CundallStrack computed it
  // (not stored: 24 bytes per contact). The friction coefficient is the material's.
  Vec3 normal_force(std::size_t k) const {
    return kn[k] * std::max(penetration[k], 0.0) * normal[k];
  }
  void clear();
  // Appends a contact with zero forces; returns its index.
  std::size_t add(std::uint32_t a, std::uint32_t b, const Eigen::Vector3i& c, double kn_value,
                  double ks_value);
  // Removes contact k by moving the last one into its place.
  void swap_remove(std::size_t k);
  std::size_t heap_bytes() const;  // allocated capacity of all arrays
  // Capacity = size + 1/8 (at least 16): the arrays grow by 1/8 instead of doubling.
  void fit();
};

struct RveState {
  PeriodicCell cell;
  Material material;
  Spheres spheres;
  Contacts contacts;
  double dt = 0;  // DEM time step [s] (YADE: 0.5 PWaveTimeStep, from the packing)
  std::int64_t iter = 0;
};

}  // namespace mpmdem::dem::native
