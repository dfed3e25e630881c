// What the MPM reads from the wire into its own types. RVE statuses
// (constitutive/rve_point_state.hpp): each protocol::RveStatus to its PointState; every fatal
// status, unknown codes included, to kFatal with the status named for the solver's message.
// The requested outputs (constitutive/rve_outputs.hpp): each OutputBits bit to its field.
#include <gtest/gtest.h>

#include <cstdint>

#include "constitutive/rve_outputs.hpp"
#include "constitutive/rve_point_state.hpp"
#include "mpmdem/protocol.hpp"

using namespace mpmdem::mpm;
namespace protocol = mpmdem::protocol;
using protocol::RveStatus;

namespace {

std::int32_t code(RveStatus s) {
  return static_cast<std::int32_t>(s);
}

PointResponse read(std::int32_t rve_status) {
  PointResponse r;
  read_rve_status(rve_status, r);
  return r;
}

}  // namespace

TEST(RvePointState, EachWireStatusHasItsState) {
  struct Case {
    std::int32_t status;
    PointState state;
    const char* failure;
  };
  for (const Case& c : {
           Case{code(RveStatus::kOk), PointState::kOk, ""},
           Case{code(RveStatus::kNoContacts), PointState::kNoContacts, ""},
           Case{code(RveStatus::kNonFinite), PointState::kFatal, "status 2 (non-finite values)"},
           Case{code(RveStatus::kExploding), PointState::kFatal,
                "status 3 (exploding kinetic energy)"},
           Case{code(RveStatus::kBackendError), PointState::kFatal, "status 4 (backend error)"},
           Case{5, PointState::kFatal, "status 5 (unknown status 5)"},
           Case{42, PointState::kFatal, "status 42 (unknown status 42)"},
           Case{-1, PointState::kFatal, "status -1 (unknown status -1)"},
       }) {
    SCOPED_TRACE("RVE status " + std::to_string(c.status));
    const PointResponse r = read(c.status);
    EXPECT_EQ(static_cast<int>(r.state), static_cast<int>(c.state));
    EXPECT_EQ(r.failure, c.failure);
  }
}

// A response that held a failure reads the next status afresh: no stale failure text.
TEST(RvePointState, ReadingAnOkStatusClearsAnEarlierFailure) {
  PointResponse r;
  read_rve_status(code(RveStatus::kExploding), r);
  ASSERT_EQ(r.state, PointState::kFatal);
  read_rve_status(code(RveStatus::kNoContacts), r);
  EXPECT_EQ(r.state, PointState::kNoContacts);
  EXPECT_EQ(r.failure, "");
}

TEST(RveOutputs, EachBitAsksForItsField) {
  const RveOutputs none = rve_outputs(0);
  EXPECT_FALSE(none.rotation || none.porosity || none.coordination || none.unbalanced_force);
  const RveOutputs all = rve_outputs(protocol::kKnownOutputs);
  EXPECT_TRUE(all.rotation && all.porosity && all.coordination && all.unbalanced_force);
  const RveOutputs a = rve_outputs(protocol::kOutputRotation | protocol::kOutputCoordination);
  EXPECT_TRUE(a.rotation && a.coordination);
  EXPECT_FALSE(a.porosity || a.unbalanced_force);
  const RveOutputs b = rve_outputs(protocol::kOutputPorosity | protocol::kOutputUnbalancedForce);
  EXPECT_TRUE(b.porosity && b.unbalanced_force);
  EXPECT_FALSE(b.rotation || b.coordination);
}
