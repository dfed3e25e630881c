// The substep tally behind dem_app's "substeps rank R" log line (substep_tally.hpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "substep_tally.hpp"

namespace mpmdem::dem {
namespace {

std::vector<protocol::RveReply> replies(const std::vector<int>& substeps) {
  std::vector<protocol::RveReply> r(substeps.size());
  for (std::size_t k = 0; k < r.size(); ++k) r[k].n_substeps = substeps[k];
  return r;
}

// Two exchanges: 2, 2, 5, 100 substeps and a skipped RVE (0), then 100 and 7: six updates
// ran substeps (2, 2, 5, 100, 100, 7; the skipped one did not). Mean 216 / 6 = 36; fewest 2
// on 2 of 6 updates (33.3 %), most 100 on 2 of 6 (33.3 %).
TEST(SubstepTally, CountsUpdatesMeanAndTheSharesAtTheFewestAndMost) {
  SubstepTally tally;
  EXPECT_EQ(tally.line(0), "");  // no update yet: no line
  const auto a = replies({2, 2, 5, 100, 0});
  const auto b = replies({100, 7});
  tally.add(a.data(), a.size());
  tally.add(b.data(), b.size());
  EXPECT_EQ(tally.updates(), 6);
  EXPECT_EQ(tally.line(3),
            "dem_app: substeps rank 3: 6 RVE updates, mean 36.00 substeps per update; fewest 2 "
            "(33.3 % of the updates), most 100 (33.3 %)");
}

// A closed-form backend (elastic) reports no substeps: nothing to log.
TEST(SubstepTally, ClosedFormBackendsLogNothing) {
  SubstepTally tally;
  const auto r = replies({0, 0, 0});
  tally.add(r.data(), r.size());
  EXPECT_EQ(tally.updates(), 0);
  EXPECT_EQ(tally.line(0), "");
}

}  // namespace
}  // namespace mpmdem::dem
