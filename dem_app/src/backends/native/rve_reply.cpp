// The reply of one native RVE from its state: see rve_reply.hpp.
#include "backends/native/rve_reply.hpp"

#include <cstring>

#include "backends/native/measures.hpp"

namespace mpmdem::dem::native {

namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

std::int32_t as_int(protocol::RveStatus s) {
  return static_cast<std::int32_t>(s);
}

}  // namespace

void reply_from_state(const RveRecord& rec, std::int32_t status, std::int32_t n_sub,
                      std::uint32_t outputs, bool stiffness, protocol::RveReply& reply) {
  std::memset(&reply, 0, sizeof reply);
  const RveState& s = rec.state;
  const bool contacts = s.contacts.size() > 0;
  if (!contacts && status == as_int(protocol::RveStatus::kOk)) {
    status = as_int(protocol::RveStatus::kNoContacts);
  }
  if (status == as_int(protocol::RveStatus::kOk)) {
    const StressStiffness ss = stress_and_stiffness(s, stiffness);
    const Eigen::Matrix3d& sig = ss.stress;
    const RowMajor3 sym = 0.5 * (sig + sig.transpose());
    if (!sym.allFinite()) {
      status = as_int(protocol::RveStatus::kNonFinite);
    } else {
      Eigen::Map<RowMajor3>(reply.stress) = sym;
      reply.stiffness = ss.stiffness;
    }
  }
  const std::uint32_t o = outputs;
  if (status == as_int(protocol::RveStatus::kOk) ||
      status == as_int(protocol::RveStatus::kNoContacts)) {
    if (o & protocol::kOutputRotation) {
      const Eigen::Vector3d rot = mean_rotation(s);
      for (int i = 0; i < 3; ++i) reply.rotation[i] = rot[i];
    }
    if (o & protocol::kOutputPorosity) reply.porosity = porosity(s);
    if (o & protocol::kOutputCoordination) reply.coordination = coordination(s);
    if ((o & protocol::kOutputUnbalancedForce) && contacts) {
      reply.unbalanced_force = rec.unbalanced;
    }
  }
  reply.status = status;
  reply.n_substeps = n_sub;
}
}  // namespace mpmdem::dem::native
