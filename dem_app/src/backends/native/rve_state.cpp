// Structure-of-arrays containers of a native RVE: see rve_state.hpp.
#include "backends/native/rve_state.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace mpmdem::dem::native {

CellDist to_cell_dist(const Eigen::Vector3i& c) {
  constexpr int kMax = std::numeric_limits<std::int16_t>::max();
  if (c.cwiseAbs().maxCoeff() >= kMax) {
    throw std::runtime_error("native backend: image offset (" + std::to_string(c[0]) + ", " +
                             std::to_string(c[1]) + ", " + std::to_string(c[2]) +
                             ") of 32767 cells or more (unwrapped positions): not supported");
  }
  return c.cast<std::int16_t>();
}

void Spheres::resize(std::size_t n) {
  radius.resize(n);
  mass.resize(n);
  inertia.resize(n);
  pos.resize(n);
  vel.resize(n);
  ang_vel.resize(n);
  ori.resize(n, Quat::Identity());
  ref_ori.resize(n, Quat::Identity());
  release_forces();
}

namespace {
// Spare buffers of the per-step scratch fields, per thread: release_forces hands an RVE's
// buffers to them and prepare_scratch takes them back for the next RVE, so a coupling step
// allocates nothing and a resident RVE still keeps no scratch.
thread_local std::vector<double> spare_scratch[8];
}  // namespace

void Spheres::prepare_scratch() {
  const std::size_t n = size();
  if (force.size() == n && inv_mass.size() == n) return;
  std::vector<double>* const f[8] = {&force.c[0],  &force.c[1],  &force.c[2], &torque.c[0],
                                     &torque.c[1], &torque.c[2], &inv_mass,   &inv_inertia};
  for (int i = 0; i < 8; ++i) {
    if (f[i]->capacity() == 0) f[i]->swap(spare_scratch[i]);
  }
  force.resize(n);
  torque.resize(n);
  inv_mass.resize(n);
  inv_inertia.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    inv_mass[i] = 1 / mass[i];
    inv_inertia[i] = 1 / inertia[i];
  }
}

void Spheres::push_back(double r, double m, double inertia_value, const Vec3& x) {
  const std::size_t n = size();
  resize(n + 1);
  radius[n] = r;
  mass[n] = m;
  inertia[n] = inertia_value;
  pos.set(n, x);
}

namespace {
template <typename T>
std::size_t cap(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
template <typename T>
void fit_to(std::vector<T>& v, std::size_t n) {
  if (v.capacity() == n) return;
  std::vector<T> w;
  w.reserve(n);
  w.assign(v.begin(), v.end());
  v.swap(w);
}
}  // namespace

std::size_t Spheres::heap_bytes() const {
  return cap(radius) + cap(mass) + cap(inertia) + pos.capacity_bytes() + vel.capacity_bytes() +
         ang_vel.capacity_bytes() + cap(ori) + cap(ref_ori) + force.capacity_bytes() +
         torque.capacity_bytes() + cap(inv_mass) + cap(inv_inertia);
}

void Spheres::release_forces() {
  std::vector<double>* const f[8] = {&force.c[0],  &force.c[1],  &force.c[2], &torque.c[0],
                                     &torque.c[1], &torque.c[2], &inv_mass,   &inv_inertia};
  for (int i = 0; i < 8; ++i) {
    if (spare_scratch[i].capacity() < f[i]->capacity()) spare_scratch[i].swap(*f[i]);
    std::vector<double>().swap(*f[i]);
  }
}

std::size_t Contacts::heap_bytes() const {
  return cap(id1) + cap(id2) + cell.capacity_bytes() + normal.capacity_bytes() +
         shear_force.capacity_bytes() + cap(penetration) + cap(normal_viscous);
}

void Contacts::fit() {
  const std::size_t n = std::max<std::size_t>(16, size() + size() / 8);
  fit_to(id1, n), fit_to(id2, n), fit_to(penetration, n);
  if (viscous) fit_to(normal_viscous, n);
  for (int a = 0; a < 3; ++a) {
    fit_to(cell.c[a], n), fit_to(normal.c[a], n), fit_to(shear_force.c[a], n);
  }
}

void Contacts::clear() {
  id1.clear();
  id2.clear();
  cell.clear();
  normal.clear();
  shear_force.clear();
  penetration.clear();
  normal_viscous.clear();
}

std::size_t Contacts::add(std::uint32_t a, std::uint32_t b, const CellDist& c) {
  if (id1.size() == id1.capacity()) fit();
  id1.push_back(a);
  id2.push_back(b);
  cell.push_back(c);
  normal.push_back(Vec3::Zero());
  shear_force.push_back(Vec3::Zero());
  penetration.push_back(0.0);
  if (viscous) normal_viscous.push_back(0.0);
  return id1.size() - 1;
}

void Contacts::move(std::size_t from, std::size_t to) {
  id1[to] = id1[from];
  id2[to] = id2[from];
  for (int a = 0; a < 3; ++a) {
    cell.c[a][to] = cell.c[a][from];
    normal.c[a][to] = normal.c[a][from];
    shear_force.c[a][to] = shear_force.c[a][from];
  }
  penetration[to] = penetration[from];
  if (viscous) normal_viscous[to] = normal_viscous[from];
}

void Contacts::truncate(std::size_t n) {
  id1.resize(n);
  id2.resize(n);
  cell.resize(n);
  normal.resize(n);
  shear_force.resize(n);
  penetration.resize(n);
  if (viscous) normal_viscous.resize(n);
}

void Contacts::swap_remove(std::size_t k) {
  const std::size_t last = size() - 1;
  if (k != last) move(last, k);
  truncate(last);
}

void Contacts::sift_back(std::size_t q) {
  const std::uint32_t a = id1[q];
  std::size_t pos = q;
  while (pos > 0 && id1[pos - 1] > a) --pos;
  if (pos == q) return;
  const auto rot = [&](auto& v) {
    std::rotate(v.begin() + static_cast<std::ptrdiff_t>(pos),
                v.begin() + static_cast<std::ptrdiff_t>(q),
                v.begin() + static_cast<std::ptrdiff_t>(q + 1));
  };
  rot(id1), rot(id2), rot(penetration);
  if (viscous) rot(normal_viscous);
  for (int c = 0; c < 3; ++c) rot(cell.c[c]), rot(normal.c[c]), rot(shear_force.c[c]);
}

void Contacts::set_viscous(bool on) {
  viscous = on;
  if (on) {
    normal_viscous.resize(size(), 0.0);
  } else {
    std::vector<double>().swap(normal_viscous);
  }
}

void set_contact_law(RveState& s, const ContactLaw& law) {
  s.law = law;
  s.contacts.set_viscous(law.viscous());
}

void Contacts::sort_by_first() {
  for (std::size_t q = 1; q < size(); ++q) sift_back(q);
}

}  // namespace mpmdem::dem::native
