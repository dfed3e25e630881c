// RVE measures as YADE's utils compute them: see measures.hpp.
#include "backends/native/measures.hpp"

#include <cmath>

namespace mpmdem::dem::native {

Eigen::Matrix3d love_weber_stress(const RveState& s) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  const auto& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec3 branch = s.spheres.pos[c.id1[k]] - s.spheres.pos[c.id2[k]] - s.cell.shift(c.cell[k]);
    sum += (normal_force(s, k) + c.shear_force[k]) * branch.transpose();
  }
  return sum / s.cell.volume();
}

double stiffness_bound(const RveState& s) {
  const auto& c = s.contacts;
  Vec3 cii = Vec3::Zero(), si = Vec3::Zero();
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec3 l = s.spheres.pos[c.id2[k]] + s.cell.shift(c.cell[k]) - s.spheres.pos[c.id1[k]];
    const double l2 = l.squaredNorm();
    const Vec3& n = c.normal[k];
    const double fs = c.shear_force[k].norm();
    const FrictPhys phys = contact_stiffness(s, k);
    const Vec3 t = fs > 0 ? Vec3(c.shear_force[k] / fs) : Vec3::Zero();
    for (int i = 0; i < 3; ++i) {
      const double ni2 = n[i] * n[i];
      cii[i] += l2 * ni2 * (phys.kn * ni2 + phys.ks * t[i] * t[i]);
      si[i] += phys.kn * l2 * ni2;
    }
  }
  const double a = s.material.ks_kn;
  double best = 0;
  for (int i = 0; i < 3; ++i) {
    const double b = a <= 1 ? (1 - a) * cii[i] + a * si[i] : cii[i] + a * si[i];
    best = std::max(best, b);
  }
  return best / s.cell.volume();
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
