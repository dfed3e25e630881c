// The contact laws by name (backends/contact_laws/registry.hpp): the names the scene key accepts,
// the mapping to native::ContactLawKind, visit_law, and the laws' functions on double against
// YADE's formulas (Ip2_FrictMat_FrictMat_FrictPhys, FrictViscoPhys's dashpot).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

#include "backends/contact_laws/registry.hpp"
#include "backends/contact_laws/table1.hpp"
#include "backends/native/contact_law.hpp"

namespace {

using namespace mpmdem::dem;

TEST(ContactLawRegistry, NamesAreTheKindsInOrder) {
  ASSERT_EQ(laws::kLaws.size(), 2u);
  EXPECT_EQ(laws::law_names(), (std::vector<std::string>{"frict", "frict_visco"}));
  EXPECT_EQ(laws::find_law("frict"), static_cast<int>(native::ContactLawKind::kFrict));
  EXPECT_EQ(laws::find_law("frict_visco"), static_cast<int>(native::ContactLawKind::kFrictVisco));
  EXPECT_EQ(laws::find_law("hertz"), -1);
  EXPECT_STREQ(native::contact_law_name(native::ContactLawKind::kFrictVisco), "frict_visco");
  EXPECT_FALSE(native::ContactLaw{}.viscous());
  EXPECT_TRUE(native::frict_visco_law(0.5).viscous());
  native::ContactLaw unknown;
  unknown.kind = static_cast<native::ContactLawKind>(7);
  EXPECT_FALSE(unknown.known());
  EXPECT_FALSE(unknown.viscous());
  EXPECT_STREQ(native::contact_law_name(unknown.kind), "unknown");
}

TEST(ContactLawRegistry, VisitGivesEachKindItsLaw) {
  const bool visco = native::visit_law(native::ContactLawKind::kFrictVisco, [](auto law) {
    return std::is_same_v<decltype(law), laws::FrictVisco>;
  });
  const bool frict = native::visit_law(native::ContactLawKind::kFrict, [](auto law) {
    return std::is_same_v<decltype(law), laws::Frict>;
  });
  EXPECT_TRUE(visco);
  EXPECT_TRUE(frict);
}

TEST(ContactLawRegistry, FrictIsYadesFrictPhysAndCundallStrack) {
  const double r1 = 1e-3, r2 = 1.3e-3, e = laws::table1::kYoung, a = laws::table1::kKsKn;
  double kn = 0, ks = 0;
  laws::Frict::stiffness(e, a, r1, r2, kn, ks);
  const native::FrictPhys y = native::frict_phys(e, r1, a, 0.5, e, r2, a, 0.5);
  EXPECT_NEAR(kn, y.kn, 1e-15 * y.kn);
  EXPECT_NEAR(ks, y.ks, 1e-15 * y.ks);
  // Normal force kn max(pen, 0) n; zero when open.
  const double n[3] = {0, 0, 1};
  double fn[3], visc = 0;
  const laws::LawParams p{e, a, 0.25, 0.0};
  laws::Frict::normal_force(p, kn, 1e-6, -0.1, 1.0, 1.0, n, fn, visc);
  EXPECT_EQ(fn[2], kn * 1e-6);
  EXPECT_EQ(visc, 0.0);
  laws::Frict::normal_force(p, kn, -1e-6, -0.1, 1.0, 1.0, n, fn, visc);
  EXPECT_EQ(fn[2], 0.0);
  // Coulomb: |fs| capped at tan(phi) |fn| (tan2 = 0.25: half of |fn|).
  const double f_open[3] = {0, 0, 2.0};
  double fs[3] = {3.0, 4.0, 0};
  laws::Frict::slide(p, f_open, fs);
  EXPECT_NEAR(std::hypot(fs[0], fs[1]), 1.0, 1e-15);
  EXPECT_NEAR(fs[1] / fs[0], 4.0 / 3.0, 1e-15);
}

TEST(ContactLawRegistry, FrictViscoAddsTheDashpotOfItsBetaN) {
  const double kn = 1e5, m1 = 2e-3, m2 = 3e-3, rn = -0.2, pen = 1e-6;
  const native::ContactLaw law = native::frict_visco_law(0.5);
  const laws::LawParams p{6e8, 0.8, 0.25, law.beta_n};
  const double n[3] = {1, 0, 0};
  double fn[3], visc = 0;
  laws::FrictVisco::normal_force(p, kn, pen, rn, m1, m2, n, fn, visc);
  const double cn = 2 * std::sqrt(m1 * m2 / (m1 + m2) * kn) * law.beta_n;
  EXPECT_NEAR(visc, cn * rn, 1e-15 * std::abs(cn * rn));
  EXPECT_NEAR(fn[0], kn * pen - cn * rn, 1e-15 * kn * pen);
  double stored[3];
  laws::FrictVisco::stored_normal_force(kn, pen, visc, n, stored);
  EXPECT_EQ(stored[0], fn[0]);  // what the stress and the energy read back, bit for bit
}

}  // namespace
