// The host storage of a batch (batch_layout.hpp's arrays as std::vectors) and its conversion
// from and to the native backend's RVE states (native::RveRecord): the batch is packed from
// native states (after initialise, restore, adopt, tiling) and unpacked into them (checkpoint,
// export, tiling), so checkpoints and migrations are the native backend's (NAT5 blobs) and a
// run checkpointed on one backend resumes on the other.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "backends/batch/batch_layout.hpp"

namespace mpmdem::dem::native {
struct RveRecord;  // backends/native/binary_state.hpp (no Eigen here: nvcc includes this file)
}

namespace mpmdem::dem::batch {

struct Capacity {
  double contacts_per_sphere = 4;  // contact slots per sphere (at least 128 per RVE)
  double pairs_per_sphere = 12;    // Verlet pair slots per sphere
};

class BatchState {
 public:
  // Lays out and fills the batch from the records (their states; Verlet lists invalid).
  using Records = std::function<const native::RveRecord&(std::size_t)>;
  void pack(std::size_t n, const Records& rves, const Capacity& cap);
  // Writes RVE r's state back into rec (spheres, contacts in the batch's order, cell, iter,
  // unbalanced); the other fields of rec are kept.
  void unpack(int r, native::RveRecord& rec) const;
  BatchView view();
  int n_rve() const { return static_cast<int>(sph0_.size()) - 1; }
  std::int64_t n_spheres() const { return sph0_.empty() ? 0 : sph0_.back(); }
  std::int64_t contact_slots() const { return con0_.empty() ? 0 : con0_.back(); }
  std::int64_t pair_slots() const { return pair0_.empty() ? 0 : pair0_.back(); }
  std::vector<StepIn>& in() { return in_; }
  std::vector<StepOut>& out() { return out_; }
  // Bytes of the arrays (what the device copy allocates).
  std::size_t bytes() const;

  // The arrays, by name, for the device mirror (batch_device.cu copies each).
  std::vector<std::int64_t> sph0_, con0_, pair0_, iter_;
  std::vector<std::int32_t> n_con_, n_pair_, flags_, inc_start_, inc_fill_, pair_of_, inc_;
  std::vector<double> cell_, dt_, young_, ks_kn_, tan2_, p0_, skin_, max_cut_, unbalanced_;
  std::vector<double> radius_, mass_, inertia_, inv_mass_, inv_inertia_, ori_, ref_ori_;
  std::vector<double> pos_[3], vel_[3], ang_[3], force_[3], torque_[3], x_ref_[3];
  std::vector<std::uint32_t> id1_, id2_, pi_, pj_;
  std::vector<std::int16_t> ccell_[3], pc_[3];
  std::vector<double> normal_[3], shear_[3], pen_, of_[3], ot1_[3], ot2_[3];
  std::vector<std::uint8_t> in_contact_;
  std::vector<StepIn> in_;
  std::vector<StepOut> out_;
};

}  // namespace mpmdem::dem::batch
