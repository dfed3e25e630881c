// Host storage of a batch and its conversion from and to native states: see batch_state.hpp.
#include "backends/batch/batch_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "backends/native/binary_state.hpp"

namespace mpmdem::dem::batch {

namespace {

void store_matrix(const Eigen::Matrix3d& m, double* p) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p[3 * i + j] = m(i, j);
}
Eigen::Matrix3d load_matrix(const double* p) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = p[3 * i + j];
  return m;
}
template <typename T>
void sized(std::vector<T>& v, std::size_t n) {
  v.assign(n, T{});
}

}  // namespace

void BatchState::pack(std::size_t nr, const Records& rves, const Capacity& cap) {
  sph0_.assign(nr + 1, 0);
  con0_.assign(nr + 1, 0);
  pair0_.assign(nr + 1, 0);
  for (std::size_t r = 0; r < nr; ++r) {
    const auto& s = rves(r).state;
    const auto n = static_cast<std::int64_t>(s.spheres.size());
    const auto nc = static_cast<std::int64_t>(s.contacts.size());
    if (n >= (std::int64_t{1} << 31)) throw std::runtime_error("cuda backend: RVE too large");
    const auto ccap = std::max<std::int64_t>(
        {128, static_cast<std::int64_t>(std::ceil(cap.contacts_per_sphere * n)), nc + nc / 4});
    const auto pcap =
        std::max<std::int64_t>(64, static_cast<std::int64_t>(std::ceil(cap.pairs_per_sphere * n)));
    sph0_[r + 1] = sph0_[r] + n;
    con0_[r + 1] = con0_[r] + ccap;
    pair0_[r + 1] = pair0_[r] + pcap;
  }
  const auto ns = static_cast<std::size_t>(sph0_[nr]), nc = static_cast<std::size_t>(con0_[nr]),
             np = static_cast<std::size_t>(pair0_[nr]);
  sized(iter_, nr), sized(n_con_, nr), sized(n_pair_, nr), sized(flags_, nr * kRveFlags);
  sized(cell_, nr * kCellDoubles);
  for (auto* v : {&dt_, &young_, &ks_kn_, &tan2_, &p0_, &skin_, &max_cut_, &unbalanced_})
    sized(*v, nr);
  sized(in_, nr), sized(out_, nr);
  for (auto* v : {&radius_, &mass_, &inertia_, &inv_mass_, &inv_inertia_}) sized(*v, ns);
  sized(ori_, 4 * ns), sized(ref_ori_, 4 * ns), sized(inc_fill_, ns), sized(inc_start_, ns + nr);
  for (int a = 0; a < 3; ++a) {
    for (auto* v : {&pos_[a], &vel_[a], &ang_[a], &force_[a], &torque_[a], &x_ref_[a]})
      sized(*v, ns);
    for (auto* v : {&normal_[a], &shear_[a], &of_[a], &ot1_[a], &ot2_[a]}) sized(*v, nc);
    sized(ccell_[a], nc), sized(pc_[a], np);
  }
  sized(id1_, nc), sized(id2_, nc), sized(pen_, nc), sized(pair_of_, nc), sized(inc_, 2 * nc);
  sized(pi_, np), sized(pj_, np), sized(in_contact_, np);
  for (std::size_t r = 0; r < nr; ++r) {
    const native::RveState& s = rves(r).state;
    double* cb = cell_.data() + r * kCellDoubles;
    store_matrix(s.cell.hsize, cb + kHsize);
    store_matrix(s.cell.trsf, cb + kTrsf);
    store_matrix(s.cell.vel_grad, cb + kVelGrad);
    store_matrix(s.cell.next_vel_grad, cb + kNextVelGrad);
    store_matrix(s.cell.prev_vel_grad, cb + kPrevVelGrad);
    store_matrix(s.cell.vgrad_times_prev_h, cb + kLh);
    flags_[r * kRveFlags + kVelGradChanged] = s.cell.vel_grad_changed ? 1 : 0;
    dt_[r] = s.dt;
    iter_[r] = s.iter;
    young_[r] = s.material.young;
    ks_kn_[r] = s.material.ks_kn;
    const double tan_phi = std::tan(s.material.friction_angle);  // native law_constants
    tan2_[r] = tan_phi * tan_phi;
    p0_[r] = rves(r).p0;
    unbalanced_[r] = rves(r).unbalanced;
    const auto& sp = s.spheres;
    const std::size_t o = static_cast<std::size_t>(sph0_[r]);
    for (std::size_t i = 0; i < sp.size(); ++i) {
      radius_[o + i] = sp.radius[i];
      mass_[o + i] = sp.mass[i];
      inertia_[o + i] = sp.inertia[i];
      inv_mass_[o + i] = 1 / sp.mass[i];
      inv_inertia_[o + i] = 1 / sp.inertia[i];
      for (int a = 0; a < 3; ++a) {
        pos_[a][o + i] = sp.pos.c[a][i];
        vel_[a][o + i] = sp.vel.c[a][i];
        ang_[a][o + i] = sp.ang_vel.c[a][i];
      }
      for (int q = 0; q < 4; ++q) {
        ori_[4 * (o + i) + q] = sp.ori[i].coeffs()[q];
        ref_ori_[4 * (o + i) + q] = sp.ref_ori[i].coeffs()[q];
      }
    }
    const auto& c = s.contacts;
    const std::size_t co = static_cast<std::size_t>(con0_[r]);
    n_con_[r] = static_cast<std::int32_t>(c.size());
    for (std::size_t k = 0; k < c.size(); ++k) {
      id1_[co + k] = c.id1[k];
      id2_[co + k] = c.id2[k];
      pen_[co + k] = c.penetration[k];
      pair_of_[co + k] = -1;
      for (int a = 0; a < 3; ++a) {
        ccell_[a][co + k] = c.cell.c[a][k];
        normal_[a][co + k] = c.normal.c[a][k];
        shear_[a][co + k] = c.shear_force.c[a][k];
      }
    }
  }
}

void BatchState::unpack(int r, native::RveRecord& rec) const {
  native::RveState& s = rec.state;
  const double* cb = cell_.data() + static_cast<std::size_t>(r) * kCellDoubles;
  s.cell.hsize = load_matrix(cb + kHsize);
  s.cell.trsf = load_matrix(cb + kTrsf);
  s.cell.vel_grad = load_matrix(cb + kVelGrad);
  s.cell.next_vel_grad = load_matrix(cb + kNextVelGrad);
  s.cell.prev_vel_grad = load_matrix(cb + kPrevVelGrad);
  s.cell.vgrad_times_prev_h = load_matrix(cb + kLh);
  s.cell.vel_grad_changed = flags_[static_cast<std::size_t>(r) * kRveFlags + kVelGradChanged] != 0;
  s.iter = iter_[r];
  rec.unbalanced = unbalanced_[r];
  auto& sp = s.spheres;
  const auto o = static_cast<std::size_t>(sph0_[r]);
  const auto n = static_cast<std::size_t>(sph0_[r + 1] - sph0_[r]);
  if (sp.size() != n) throw std::logic_error("batch unpack: sphere count changed");
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      sp.pos.c[a][i] = pos_[a][o + i];
      sp.vel.c[a][i] = vel_[a][o + i];
      sp.ang_vel.c[a][i] = ang_[a][o + i];
    }
    for (int q = 0; q < 4; ++q) sp.ori[i].coeffs()[q] = ori_[4 * (o + i) + q];
  }
  auto& c = s.contacts;
  c.clear();
  const auto co = static_cast<std::size_t>(con0_[r]);
  for (std::int32_t k = 0; k < n_con_[r]; ++k) {
    const std::size_t q = co + static_cast<std::size_t>(k);
    const std::size_t m =
        c.add(id1_[q], id2_[q], native::CellDist(ccell_[0][q], ccell_[1][q], ccell_[2][q]));
    c.normal.set(m, native::Vec3(normal_[0][q], normal_[1][q], normal_[2][q]));
    c.shear_force.set(m, native::Vec3(shear_[0][q], shear_[1][q], shear_[2][q]));
    c.penetration[m] = pen_[q];
  }
  sp.release_forces();
}

BatchView BatchState::view() {
  BatchView v;
  v.n_rve = n_rve();
  v.sph0 = sph0_.data(), v.con0 = con0_.data(), v.pair0 = pair0_.data();
  v.n_con = n_con_.data(), v.n_pair = n_pair_.data(), v.cell = cell_.data(),
  v.flags = flags_.data();
  v.dt = dt_.data(), v.young = young_.data(), v.ks_kn = ks_kn_.data(), v.tan2 = tan2_.data();
  v.p0 = p0_.data(), v.skin = skin_.data(), v.max_cut = max_cut_.data();
  v.unbalanced = unbalanced_.data(), v.iter = iter_.data();
  v.in = in_.data(), v.out = out_.data();
  v.radius = radius_.data(), v.mass = mass_.data(), v.inertia = inertia_.data();
  v.inv_mass = inv_mass_.data(), v.inv_inertia = inv_inertia_.data();
  v.ori = ori_.data(), v.ref_ori = ref_ori_.data();
  v.inc_start = inc_start_.data(), v.inc_fill = inc_fill_.data();
  v.id1 = id1_.data(), v.id2 = id2_.data(), v.pen = pen_.data(), v.pair_of = pair_of_.data();
  v.inc = inc_.data(), v.pi = pi_.data(), v.pj = pj_.data(), v.in_contact = in_contact_.data();
  for (int a = 0; a < 3; ++a) {
    v.pos[a] = pos_[a].data(), v.vel[a] = vel_[a].data(), v.ang[a] = ang_[a].data();
    v.force[a] = force_[a].data(), v.torque[a] = torque_[a].data(), v.x_ref[a] = x_ref_[a].data();
    v.ccell[a] = ccell_[a].data(), v.normal[a] = normal_[a].data(), v.shear[a] = shear_[a].data();
    v.of[a] = of_[a].data(), v.ot1[a] = ot1_[a].data(), v.ot2[a] = ot2_[a].data();
    v.pc[a] = pc_[a].data();
  }
  return v;
}

std::size_t BatchState::bytes() const {
  const std::size_t nr = sph0_.empty() ? 0 : sph0_.size() - 1;
  const auto ns = static_cast<std::size_t>(n_spheres()),
             nc = static_cast<std::size_t>(contact_slots()),
             np = static_cast<std::size_t>(pair_slots());
  return nr * (kCellDoubles * 8 + kRveFlags * 4 + 8 * 8 + 3 * 8 + 4 * 2 + sizeof(StepIn) +
               sizeof(StepOut)) +
         ns * (5 * 8 + 8 * 8 + 18 * 8 + 8) + nc * (8 + 6 + 7 * 8 + 9 * 8 + 4 + 8) +
         np * (8 + 6 + 1);
}

}  // namespace mpmdem::dem::batch
