// RVE measures as YADE's utils compute them: see measures.hpp.
#include "backends/native/measures.hpp"

#include <cmath>

namespace mpmdem::dem::native {

StressStiffness stress_and_stiffness(const RveState& s, bool stiffness) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Vec3 cii = Vec3::Zero(), si = Vec3::Zero();
  const auto& c = s.contacts;
  const auto& pos = s.spheres.pos;
  for (std::size_t k = 0; k < c.size(); ++k) {
    // Branch x1 - x2 - H c (and l = x2 + H c - x1 for the bound): most contacts lie inside
    // the cell, where the zero shift changes no bit.
    const bool image = c.cell[k] != CellDist::Zero();
    const Vec3 shift = image ? s.cell.shift(c.cell[k]) : Vec3::Zero();
    const Vec3 x1 = pos[c.id1[k]], x2 = pos[c.id2[k]];
    const Vec3 branch = image ? Vec3(x1 - x2 - shift) : Vec3(x1 - x2);
    const FrictPhys phys = contact_stiffness(s, k);
    const Vec3 fn = phys.kn * std::max(c.penetration[k], 0.0) * c.normal[k];
    sum += (fn + c.shear_force[k]) * branch.transpose();
    if (!stiffness) continue;
    const Vec3 l = image ? Vec3(x2 + shift - x1) : Vec3(-branch);
    const double l2 = l.squaredNorm();
    const Vec3& n = c.normal[k];
    const double fs2 = c.shear_force[k].squaredNorm();
    const double inv_fs2 = fs2 > 0 ? 1 / fs2 : 0.0;  // t_i^2 = fs_i^2 / |fs|^2
    for (int i = 0; i < 3; ++i) {
      const double ni2 = n[i] * n[i];
      const double ti2 = c.shear_force[k][i] * c.shear_force[k][i] * inv_fs2;
      cii[i] += l2 * ni2 * (phys.kn * ni2 + phys.ks * ti2);
      si[i] += phys.kn * l2 * ni2;
    }
  }
  const double volume = s.cell.volume();
  StressStiffness out{sum / volume, 0.0};
  if (!stiffness) return out;
  const double a = s.material.ks_kn;
  for (int i = 0; i < 3; ++i) {
    const double b = a <= 1 ? (1 - a) * cii[i] + a * si[i] : cii[i] + a * si[i];
    out.stiffness = std::max(out.stiffness, b);
  }
  out.stiffness /= volume;
  return out;
}

Eigen::Matrix3d love_weber_stress(const RveState& s) {
  return stress_and_stiffness(s, false).stress;
}

double kinetic_energy(const RveState& s) {
  const auto& sp = s.spheres;
  double e = 0;
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const Vec3 v = sp.vel[i] - s.cell.prev_vel_grad * sp.pos[i];
    e += 0.5 * sp.mass[i] * v.squaredNorm();
    e += 0.5 * sp.inertia[i] * sp.ang_vel[i].squaredNorm();
  }
  return e;
}

double elastic_energy(const RveState& s) {
  const auto& c = s.contacts;
  double e = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const FrictPhys phys = contact_stiffness(s, k);
    e += 0.5 *
         (normal_force(s, k).squaredNorm() / phys.kn + c.shear_force[k].squaredNorm() / phys.ks);
  }
  return e;
}

Eigen::Vector3d mean_rotation(const RveState& s) {
  const auto& sp = s.spheres;
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const Eigen::AngleAxisd aa(sp.ref_ori[i].conjugate() * sp.ori[i]);
    sum += aa.axis() * aa.angle();
  }
  return sp.size() ? Vec3(sum / static_cast<double>(sp.size())) : Vec3::Zero();
}

double porosity(const RveState& s) {
  double v = 0;
  for (double r : s.spheres.radius) v += 4.0 / 3.0 * M_PI * r * r * r;
  return 1.0 - v / std::abs(s.cell.volume());
}

double coordination(const RveState& s) {
  return s.spheres.size()
             ? 2.0 * static_cast<double>(s.contacts.size()) / static_cast<double>(s.spheres.size())
             : 0.0;
}

double unbalanced_force(const RveState& s) {
  const auto& sp = s.spheres;
  const auto& c = s.contacts;
  if (sp.size() == 0 || c.size() == 0 || sp.force.size() != sp.size()) return 0.0;
  double body = 0, contact = 0;
  for (const auto& f : sp.force) body += f.norm();
  for (std::size_t k = 0; k < c.size(); ++k) {
    contact += (normal_force(s, k) + c.shear_force[k]).norm();
  }
  return (body / static_cast<double>(sp.size())) / (contact / static_cast<double>(c.size()));
}

}  // namespace mpmdem::dem::native
