// Material points, structure of arrays. Names follow the maths: x_p, v_p, F_p, ...
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "constitutive/point_state.hpp"

namespace mpmdem::mpm {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct Particles {
  std::vector<std::int64_t> id;       // stable id (index at creation); survives removals
  std::vector<int> region;            // index into Scene::regions
  std::vector<double> m;              // mass [kg] (constant: mass is conserved exactly)
  std::vector<double> V;              // current volume [m^3]
  std::vector<double> V0;             // initial volume [m^3]
  std::vector<Vec3> x;                // position [m]
  std::vector<Vec3> x0;               // initial position [m]
  std::vector<Vec3> v;                // velocity [m/s]
  std::vector<Mat3> C;                // APIC affine velocity matrix C_p = B_p D_p^-1 [1/s]
  std::vector<Mat3> F;                // deformation gradient
  std::vector<Mat3> dF;               // incremental deformation gradient of the last step
  std::vector<Mat3> sigma;            // Cauchy stress, tension positive [Pa]
  std::vector<double> stiffness;      // constrained modulus estimate from the provider [Pa]
  std::vector<double> strain_energy;  // elastic strain energy [J] where the model defines it
  // Optional RVE outputs (filled only when the scene requests them).
  std::vector<Vec3> rotation;
  std::vector<double> porosity;
  std::vector<double> coordination;
  std::vector<double> unbalanced_force;
  std::vector<PointState> state;  // of the last update: kOk or kNoContacts

  std::size_t size() const { return m.size(); }
};

}  // namespace mpmdem::mpm
