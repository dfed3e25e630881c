// RVE measures as YADE's utils compute them: see measures.hpp.
#include "backends/native/measures.hpp"

#include <algorithm>
#include <cmath>

#include "backends/native/contact_kernel.hpp"
#include "backends/native/simd_clones.hpp"

namespace mpmdem::dem::native {

namespace {

// Love-Weber sum and the stiffness sums over the contacts in kLanes interleaved partial sums
// (contact k goes to lane k mod kLanes), added up lane by lane at the end. The contributions
// of a chunk of contacts are computed by one loop that vectorises (SIMD clones), then added
// to the lanes in contact order: every clone gives the same bits.
constexpr int kLanes = 8;
constexpr std::size_t kChunk = kContactChunk;  // a multiple of kLanes
static_assert(kChunk % kLanes == 0);
constexpr int kTerms = 15;  // 9 stress, 3 C_ii, 3 S_i
// Per contact of a chunk: (Fn + Fs) branch^T, l^2 n_i^2 (kn n_i^2 + ks t_i^2), kn l^2 n_i^2.
struct Contributions {
  double v[kTerms][kChunk];
};

// Law: the RVE's contact law (backends/contact_laws/); a viscous one's normal force includes its
// viscous part visc (Contacts::normal_viscous); otherwise visc is unused (nullptr).
template <class Law>
MPMDEM_ALWAYS_INLINE void contributions_body(
    std::size_t m, const double (&h)[3][3], double young, double ks_kn,
    const StagedContacts* __restrict st, const double* __restrict nx, const double* __restrict ny,
    const double* __restrict nz, const double* __restrict sx, const double* __restrict sy,
    const double* __restrict sz, const double* __restrict pen, const double* __restrict x0,
    const double* __restrict x1, const double* __restrict x2, const double* __restrict rad,
    const double* __restrict visc, Contributions* __restrict out) {
  const double* const pos[3] = {x0, x1, x2};
  for (std::size_t k = 0; k < m; ++k) {
    const std::int64_t a = st->a[k], b = st->b[k];
    const double c[3] = {st->c[0][k], st->c[1][k], st->c[2][k]};
    const double n[3] = {nx[k], ny[k], nz[k]};
    const double fs[3] = {sx[k], sy[k], sz[k]};
    // l = x2 + H c - x1 (branch vector 1 -> 2); Love-Weber's branch is -l.
    double l[3];
    for (int q = 0; q < 3; ++q) {
      l[q] = (pos[q][b] + (h[q][0] * c[0] + h[q][1] * c[1] + h[q][2] * c[2])) - pos[q][a];
    }
    double kn, ks, fn[3];
    Law::stiffness(young, ks_kn, rad[a], rad[b], kn, ks);
    const double vn = Law::kViscous ? visc[k] : 0.0;
    Law::stored_normal_force(kn, pen[k], vn, n, fn);
    for (int i = 0; i < 3; ++i) {
      const double f = fn[i] + fs[i];
      for (int j = 0; j < 3; ++j) out->v[3 * i + j][k] = f * -l[j];
    }
    const double l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    const double fs2 = fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2];
    const double inv = 1 / fs2;
    const double inv_fs2 = fs2 > 0 ? inv : 0.0;  // t_i^2 = fs_i^2 / |fs|^2
    for (int i = 0; i < 3; ++i) {
      const double ni2 = n[i] * n[i];
      const double ti2 = fs[i] * fs[i] * inv_fs2;
      out->v[9 + i][k] = l2 * ni2 * (kn * ni2 + ks * ti2);
      out->v[12 + i][k] = kn * l2 * ni2;
    }
  }
}

// One loop per law, compiled for AVX-512, AVX2 and the baseline (SIMD clones).
template <class Law>
MPMDEM_SIMD_CLONES void contributions(std::size_t m, const double (&h)[3][3], double young,
                                      double ks_kn, const StagedContacts* __restrict st,
                                      const double* __restrict nx, const double* __restrict ny,
                                      const double* __restrict nz, const double* __restrict sx,
                                      const double* __restrict sy, const double* __restrict sz,
                                      const double* __restrict pen, const double* __restrict x0,
                                      const double* __restrict x1, const double* __restrict x2,
                                      const double* __restrict rad, const double* __restrict visc,
                                      Contributions* __restrict out) {
  contributions_body<Law>(m, h, young, ks_kn, st, nx, ny, nz, sx, sy, sz, pen, x0, x1, x2, rad,
                          visc, out);
}

// lanes[t][k mod kLanes] += out.v[t][k] for k < m, in the order of k.
void add_to_lanes(double (&lanes)[kTerms][kLanes], const Contributions& out, std::size_t m) {
  const std::size_t full = m / kLanes * kLanes;
  for (int t = 0; t < kTerms; ++t) {
    for (std::size_t k0 = 0; k0 < full; k0 += kLanes) {
      for (int j = 0; j < kLanes; ++j) lanes[t][j] += out.v[t][k0 + j];
    }
    for (std::size_t k = full; k < m; ++k) lanes[t][k - full] += out.v[t][k];
  }
}

}  // namespace

StressStiffness stress_and_stiffness(const RveState& s, bool stiffness) {
  const auto& c = s.contacts;
  double h[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) h[a][b] = s.cell.hsize(a, b);
  double lanes[kTerms][kLanes] = {};
  static_assert(kTerms == 15 && kLanes == 8, "stress_terms_records' lanes");
  Contributions out;
  StagedContacts st;
  const bool done = stress_terms_records(s, h, lanes);  // with AVX-512
  for (std::size_t k0 = 0; !done && k0 < c.size(); k0 += kChunk) {
    const std::size_t m = std::min(kChunk, c.size() - k0);
    stage_contacts(s, k0, m, st);
    visit_law(s.law.kind, [&](auto law) {
      using Law = decltype(law);
      contributions<Law>(
          m, h, s.material.young, s.material.ks_kn, &st, c.normal.c[0].data() + k0,
          c.normal.c[1].data() + k0, c.normal.c[2].data() + k0, c.shear_force.c[0].data() + k0,
          c.shear_force.c[1].data() + k0, c.shear_force.c[2].data() + k0, c.penetration.data() + k0,
          s.spheres.pos.c[0].data(), s.spheres.pos.c[1].data(), s.spheres.pos.c[2].data(),
          s.spheres.radius.data(), Law::kViscous ? c.normal_viscous.data() + k0 : nullptr, &out);
    });
    add_to_lanes(lanes, out, m);
  }
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Vec3 cii = Vec3::Zero(), si = Vec3::Zero();
  for (int j = 0; j < kLanes; ++j) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) sum(a, b) += lanes[3 * a + b][j];
      cii[a] += lanes[9 + a][j];
      si[a] += lanes[12 + a][j];
    }
  }
  const double volume = s.cell.volume();
  StressStiffness out_ss{sum / volume, 0.0};
  if (!stiffness) return out_ss;
  const double a = s.material.ks_kn;
  for (int i = 0; i < 3; ++i) {
    const double b = a <= 1 ? (1 - a) * cii[i] + a * si[i] : cii[i] + a * si[i];
    out_ss.stiffness = std::max(out_ss.stiffness, b);
  }
  out_ss.stiffness /= volume;
  return out_ss;
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
    e += 0.5 * (elastic_normal_force(s, k).squaredNorm() / phys.kn +
                c.shear_force[k].squaredNorm() / phys.ks);
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
  for (std::size_t i = 0; i < sp.size(); ++i) body += sp.force[i].norm();
  for (std::size_t k = 0; k < c.size(); ++k) {
    contact += (normal_force(s, k) + c.shear_force[k]).norm();
  }
  return (body / static_cast<double>(sp.size())) / (contact / static_cast<double>(c.size()));
}

}  // namespace mpmdem::dem::native
