// The whole state of one native RVE, as a structure of arrays: one contiguous array per
// field, vector fields xyz split (Split3; quaternions interleaved), so a step streams through
// memory and the layout maps onto one GPU thread block per RVE later. Nothing here allocates per
// step.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "backends/contact_laws/table1.hpp"
#include "backends/native/contact_law.hpp"
#include "backends/native/periodic_cell.hpp"

namespace mpmdem::dem::native {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// FrictMat: the material of every sphere of an RVE (YADE's packings use one).
// Image offset of a contact or Verlet pair (Interaction::cellDist), 6 bytes: |c| < 2^15
// (to_cell_dist checks it).
using CellDist = Eigen::Matrix<std::int16_t, 3, 1>;
CellDist to_cell_dist(const Eigen::Vector3i& c);

struct Material {
  double young = laws::table1::kYoung;  // contact modulus E [Pa]
  double ks_kn = laws::table1::kKsKn;   // FrictMat.poisson: ks/kn (Ip2_FrictMat_FrictMat_FrictPhys)
  double density = laws::table1::kDensity;  // [kg/m3]
  double friction_angle = 0;                // [rad]; tan of it caps |Fs|/|Fn|
};

// A per-sphere or per-contact vector field stored xyz split: one contiguous array per
// component, so that the loops over spheres and contacts read and write it with unit stride
// (and vectorise). V is the vector type handed out (Vec3 or CellDist), T its scalar.
template <typename T, typename V>
struct Split3 {
  std::vector<T> c[3];
  // By value (const: assigning to it does not compile; use set).
  const V operator[](std::size_t k) const { return V(c[0][k], c[1][k], c[2][k]); }
  void set(std::size_t k, const V& v) {
    for (int a = 0; a < 3; ++a) c[a][k] = v[a];
  }
  void push_back(const V& v) {
    for (int a = 0; a < 3; ++a) c[a].push_back(v[a]);
  }
  void pop_back() {
    for (auto& x : c) x.pop_back();
  }
  void clear() {
    for (auto& x : c) x.clear();
  }
  void resize(std::size_t n) {
    for (auto& x : c) x.resize(n);
  }
  std::size_t size() const { return c[0].size(); }
  void release() {
    for (auto& x : c) std::vector<T>().swap(x);
  }
  std::size_t capacity_bytes() const {
    return (c[0].capacity() + c[1].capacity() + c[2].capacity()) * sizeof(T);
  }
};

struct Spheres {
  std::vector<double> radius, mass, inertia;  // per sphere [m], [kg], [kg m2]
  Split3<double, Vec3> pos, vel, ang_vel;     // unwrapped positions, as YADE keeps them
  std::vector<Quat> ori, ref_ori;             // orientation, and the one rotation counts from
  // Scratch of the DEM steps: force and torque (accumulated in a step), 1 / mass and
  // 1 / inertia (for Newton). The backend releases them after each coupling step
  // (release_forces; resize does too), compute_forces sizes them again (prepare_scratch), so
  // a resident RVE does not keep them.
  Split3<double, Vec3> force, torque;
  std::vector<double> inv_mass, inv_inertia;
  std::size_t size() const { return radius.size(); }
  void resize(std::size_t n);
  void prepare_scratch();
  void push_back(double r, double m, double inertia_value, const Vec3& x);
  std::size_t heap_bytes() const;  // allocated capacity of all arrays
  void release_forces();
};

// Real contacts (Interaction with ScGeom + FrictPhys): body 2's image is pos2 + hsize * cell.
// Structure of arrays, vector fields xyz split (Split3), kept so between steps: the contact
// loop streams through them. kn and ks are not stored: they follow from the two radii and
// the RVE's one material (contact_stiffness); nor is the normal force (normal_force).
struct Contacts {
  std::vector<std::uint32_t> id1, id2;
  Split3<std::int16_t, CellDist> cell;  // Interaction::cellDist
  Split3<double, Vec3> normal;          // ScGeom::normal (unit, 1 -> 2)
  Split3<double, Vec3> shear_force;     // FrictPhys::shearForce (rotated with the contact)
  std::vector<double> penetration;      // ScGeom::penetrationDepth (last step)
  // FrictViscoPhys::normalViscous as a signed magnitude along the normal, c_n (n . v) (last
  // step): kept only when `viscous` (the frict_visco law, set_contact_law); empty otherwise.
  bool viscous = false;
  std::vector<double> normal_viscous;
  std::size_t size() const { return id1.size(); }
  void clear();
  // Appends a contact with zero forces; returns its index.
  std::size_t add(std::uint32_t a, std::uint32_t b, const CellDist& c);
  // Removes contact k by moving the last one into its place.
  void swap_remove(std::size_t k);
  // Moves contact `from` to index `to` (to < from; compaction keeping the order).
  void move(std::size_t from, std::size_t to);
  // Keeps the first n contacts.
  void truncate(std::size_t n);
  // Moves contact q back past the contacts before it with a larger first sphere (one step
  // of an insertion sort; the others keep their order): contacts sorted by first sphere
  // before q stay sorted, so that the force scatter finds each sphere's contacts together.
  void sift_back(std::size_t q);
  // Stable sort by first sphere (once, for contacts read from a YADE packing).
  void sort_by_first();
  std::size_t heap_bytes() const;  // allocated capacity of all arrays
  // Capacity = size + 1/8 (at least 16): the arrays grow by 1/8 instead of doubling.
  void fit();
  // Keep normal_viscous (sized with zeros) or not (released).
  void set_viscous(bool on);
};

struct RveState {
  PeriodicCell cell;
  Material material;
  ContactLaw law;  // set with set_contact_law
  Spheres spheres;
  Contacts contacts;
  double dt = 0;  // DEM time step [s] (YADE: 0.5 PWaveTimeStep, from the packing)
  std::int64_t iter = 0;
};

// kn and ks of contact k: the RVE's law's stiffness (contact_laws/frict.hpp: Ip2_FrictMat_FrictMat_
// FrictPhys from the two radii and the RVE's one material), the same bits as the kernels';
// tan_phi 0.
inline FrictPhys contact_stiffness(const RveState& s, std::size_t k) {
  const Material& m = s.material;
  const double r1 = s.spheres.radius[s.contacts.id1[k]];
  const double r2 = s.spheres.radius[s.contacts.id2[k]];
  FrictPhys f;
  visit_law(s.law.kind,
            [&](auto law) { decltype(law)::stiffness(m.young, m.ks_kn, r1, r2, f.kn, f.ks); });
  f.tan_phi = 0;
  return f;
}

// The law of every contact of s (and the contacts' normal_viscous kept or released with it).
void set_contact_law(RveState& s, const ContactLaw& law);

// FrictPhys::normalForce of the last step, recomputed exactly as the law computed it (its
// stored_normal_force); with frict_visco its dashpot part included
// (FrictViscoPhys::normalForce).
inline Vec3 normal_force(const RveState& s, std::size_t k) {
  const double kn = contact_stiffness(s, k).kn;
  const Vec3 nv = s.contacts.normal[k];
  const double n[3] = {nv[0], nv[1], nv[2]};
  const double visc = s.contacts.viscous ? s.contacts.normal_viscous[k] : 0.0;
  double fn[3];
  visit_law(s.law.kind, [&](auto law) {
    decltype(law)::stored_normal_force(kn, s.contacts.penetration[k], visc, n, fn);
  });
  return Vec3(fn[0], fn[1], fn[2]);
}

// Its elastic part kn max(pen, 0) n (the spring's energy).
inline Vec3 elastic_normal_force(const RveState& s, std::size_t k) {
  return contact_stiffness(s, k).kn * std::max(s.contacts.penetration[k], 0.0) *
         s.contacts.normal[k];
}

}  // namespace mpmdem::dem::native
