// Native backend's Verlet list: under random homogeneous deformations of the sheared periodic
// cell plus random sphere motions, the overlaps among the list's pairs are exactly the
// overlaps that an all-pairs search over periodic images finds (no contact missed, none
// duplicated), while the list is rebuilt only when the skin may be used up: not by a
// homogeneous deformation that leaves every pair's separation nearly as it was, however far
// from the origin the (unwrapped) spheres are; and when it is rebuilt changes no result.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <tuple>

#include "backends/native/integrator.hpp"
#include "backends/native/neighbour_list.hpp"
#include "backends/native/packing.hpp"

namespace {

using namespace mpmdem::dem::native;
using Key = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;

// The lattice shift that brings a reduced separation f nearest to 0 (the build's rounding).
Eigen::Vector3i nearest_shift(const Vec3& f) {
  return {-static_cast<int>(std::lround(f[0])), -static_cast<int>(std::lround(f[1])),
          -static_cast<int>(std::lround(f[2]))};
}

// Every overlapping (i < j, image c): |x_j + H c - x_i| < r_i + r_j, images within +-2 cells
// of the minimum image.
std::set<Key> all_pairs(const RveState& s) {
  std::set<Key> out;
  const auto& sp = s.spheres;
  const Eigen::Matrix3d h = s.cell.hsize, hinv = h.inverse();
  for (std::uint32_t i = 0; i < sp.size(); ++i) {
    for (std::uint32_t j = i + 1; j < sp.size(); ++j) {
      const Vec3 d = sp.pos[j] - sp.pos[i];
      const Vec3 f = hinv * d;
      const Eigen::Vector3i c0 = nearest_shift(f);
      const double r = sp.radius[i] + sp.radius[j];
      for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b)
          for (int c = -2; c <= 2; ++c) {
            const Eigen::Vector3i cell = c0 + Eigen::Vector3i(a, b, c);
            if ((d + h * cell.cast<double>()).squaredNorm() < r * r) {
              out.emplace(i, j, cell[0], cell[1], cell[2]);
            }
          }
    }
  }
  return out;
}

// The overlapping pairs among the list's pairs (the only ones compute_forces tests).
std::set<Key> list_pairs(const RveState& s, const NeighbourList& nl) {
  std::set<Key> out;
  const auto& sp = s.spheres;
  for (std::uint32_t i = 0; i < sp.size(); ++i) {
    for (std::size_t p = nl.row_begin(i); p < nl.row_begin(i + 1); ++p) {
      const std::uint32_t j = nl.pair_j(p);
      const Eigen::Vector3i c = nl.pair_cell(p).cast<int>();
      const double r = sp.radius[i] + sp.radius[j];
      const Vec3 d = sp.pos[j] + s.cell.shift(c) - sp.pos[i];
      if (d.squaredNorm() < r * r) {
        const bool fresh = out.emplace(i, j, c[0], c[1], c[2]).second;
        EXPECT_TRUE(fresh) << "pair listed twice: " << i << " " << j;
      }
    }
  }
  return out;
}

// 150 spheres (seed 7) shrunk homogeneously to porosity ~0.5: overlaps everywhere.
RveState dense_cloud() {
  CloudParams cp;
  cp.n_spheres = 150;
  cp.seed = 7;
  RveState s = build_cloud(cp);
  const double shrink = 0.8;
  s.cell.hsize *= shrink;
  for (auto& x : s.spheres.pos.c) {
    for (double& v : x) v *= shrink;
  }
  return s;
}

TEST(NativeNeighbourList, FindsExactlyTheAllPairsContactsUnderRandomDeformation) {
  RveState s = dense_cloud();
  NeighbourList nl(0.5);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r_min = *std::min_element(s.spheres.radius.begin(), s.spheres.radius.end());
  const int steps = 60;
  std::size_t checked = 0;
  for (int k = 0; k < steps; ++k) {
    // Random homogeneous increment (stretch and shear up to 1e-3) and random fluctuations.
    Eigen::Matrix3d df = Eigen::Matrix3d::Identity();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) df(a, b) += 1e-3 * u(rng);
    s.cell.hsize = df * s.cell.hsize;
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
      s.spheres.pos.set(i, df * s.spheres.pos[i] + 0.01 * r_min * Vec3(u(rng), u(rng), u(rng)));
    }
    if (k == steps / 2) {  // one large jump of a few spheres: must force a rebuild
      for (std::size_t i = 0; i < 5; ++i)
        s.spheres.pos.set(i, s.spheres.pos[i] + 0.3 * r_min * Vec3(1, -1, 0.5));
    }
    nl.ensure(s);
    const std::set<Key> expected = all_pairs(s), found = list_pairs(s, nl);
    ASSERT_EQ(found, expected) << "step " << k;
    checked += expected.size();
  }
  EXPECT_GT(checked, 100u * steps);  // a dense packing: many contacts per check
  // Rebuilt more than once (the skin is used up), far less often than every step.
  EXPECT_GE(nl.rebuilds(), 2);
  EXPECT_LT(nl.rebuilds(), steps / 2);
}

// The list's rows, row by row, as the all-pairs build lists them: for every j > i in
// ascending order, the images within r_i + r_j + skin among the 27 around the minimum one.
using Row = std::vector<std::tuple<std::uint32_t, int, int, int>>;
std::vector<Row> all_pairs_rows(const RveState& s, double skin) {
  const auto& sp = s.spheres;
  const Eigen::Matrix3d h = s.cell.hsize, hinv = h.inverse();
  std::vector<Row> rows(sp.size());
  for (std::uint32_t i = 0; i < sp.size(); ++i) {
    for (std::uint32_t j = i + 1; j < sp.size(); ++j) {
      const Vec3 d = sp.pos[j] - sp.pos[i];
      const Vec3 f = hinv * d;
      const Eigen::Vector3i c0 = nearest_shift(f);
      const Vec3 d0 = d + h * c0.cast<double>();
      const double cut = sp.radius[i] + sp.radius[j] + skin;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b)
          for (int c = -1; c <= 1; ++c) {
            if ((d0 + h * Vec3(a, b, c)).squaredNorm() < cut * cut) {
              rows[i].emplace_back(j, c0[0] + a, c0[1] + b, c0[2] + c);
            }
          }
    }
  }
  return rows;
}

std::vector<Row> list_rows(const RveState& s, const NeighbourList& nl) {
  std::vector<Row> rows(s.spheres.size());
  for (std::uint32_t i = 0; i < s.spheres.size(); ++i) {
    for (std::size_t p = nl.row_begin(i); p < nl.row_begin(i + 1); ++p) {
      const Eigen::Vector3i c = nl.pair_cell(p).cast<int>();
      rows[i].emplace_back(nl.pair_j(p), c[0], c[1], c[2]);
    }
  }
  return rows;
}

// The build searches only neighbouring bins of the cell's reduced frame, yet lists exactly
// the pairs of the all-pairs build in its order (what keeps results bit for bit): on clouds
// of 800 spheres stretched and sheared into long, skewed cells (~30 bins along one lattice
// vector, 2 along another: searched whole), every sphere moved by whole periods up to 30 cells
// from the origin (positions are not wrapped), and on a small cell (2 bins on every axis:
// the all-pairs loop itself).
TEST(NativeNeighbourList, BinnedBuildListsTheAllPairsBuildsPairsInItsOrder) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> period(-30, 30);
  const Eigen::Matrix3d stretch = Eigen::Vector3d(4.0, 0.25, 1.0).asDiagonal();
  Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
  shear(0, 1) = 0.7, shear(2, 0) = -0.3;
  struct Case {
    Eigen::Matrix3d df;
    bool binned;  // searched by bins (else every pair: 2 bins on every axis)
  };
  for (const Case& c : {Case{stretch, true}, Case{shear * stretch, true},
                        Case{0.3 * Eigen::Matrix3d::Identity(), false}}) {
    const Eigen::Matrix3d& df = c.df;
    CloudParams cp;
    cp.n_spheres = 800;
    cp.seed = 9;
    RveState s = build_cloud(cp);
    s.cell.hsize = df * s.cell.hsize;
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
      const Vec3 shift = s.cell.hsize * Vec3(period(rng), period(rng), period(rng));
      s.spheres.pos.set(i, df * s.spheres.pos[i] + shift);
    }
    NeighbourList nl(0.5);
    nl.ensure(s);
    ASSERT_EQ(nl.rebuilds(), 1);
    EXPECT_EQ(nl.binned_builds(), c.binned ? 1 : 0);  // the path this case is meant to test
    const double r_min = *std::min_element(s.spheres.radius.begin(), s.spheres.radius.end());
    const std::vector<Row> expected = all_pairs_rows(s, 0.5 * r_min), found = list_rows(s, nl);
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      ASSERT_EQ(found[i], expected[i]) << "row " << i;
      pairs += expected[i].size();
    }
    EXPECT_EQ(nl.n_pairs(), pairs);
    EXPECT_GT(pairs, s.spheres.size());  // many pairs (and images) to miss
  }
}

// A homogeneous shear of 5 % in 50 increments, every sphere 20-40 periods from the origin
// (positions are not wrapped into the cell): the spheres move by up to ~2 cm, 50 skins, yet
// no pair's separation changes by more than 5 % of its cutoff, so the list built first is
// kept (a check on the spheres' displacements, as until 2026-11-27, rebuilt it at every
// increment) and still finds exactly the all-pairs overlaps.
TEST(NativeNeighbourList, HomogeneousShearFarFromTheOriginKeepsTheList) {
  RveState s = dense_cloud();
  const Vec3 periods = s.cell.hsize * Vec3(40, -25, 30);
  for (std::size_t i = 0; i < s.spheres.size(); ++i)
    s.spheres.pos.set(i, s.spheres.pos[i] + periods);
  NeighbourList nl(0.5);
  nl.ensure(s);
  ASSERT_EQ(nl.rebuilds(), 1);
  const int steps = 50;
  double moved = 0;
  const std::vector<double> x0 = s.spheres.pos.c[0];
  for (int k = 0; k < steps; ++k) {
    Eigen::Matrix3d df = Eigen::Matrix3d::Identity();
    df(0, 1) = 0.05 / steps;
    s.cell.hsize = df * s.cell.hsize;
    for (std::size_t i = 0; i < s.spheres.size(); ++i) s.spheres.pos.set(i, df * s.spheres.pos[i]);
    nl.ensure(s);
    if (k % 10 == 9) {  // the all-pairs search is slow under ASan: every 10th increment
      ASSERT_EQ(list_pairs(s, nl), all_pairs(s)) << "step " << k;
    }
  }
  for (std::size_t i = 0; i < s.spheres.size(); ++i) {
    moved = std::max(moved, std::abs(s.spheres.pos.c[0][i] - x0[i]));
  }
  const double r_min = *std::min_element(s.spheres.radius.begin(), s.spheres.radius.end());
  EXPECT_GT(moved, 20 * 0.5 * r_min);  // the spheres moved by many skins
  EXPECT_EQ(nl.rebuilds(), 1);
}

// dem_step with the list kept between steps and with one rebuilt at every step: the same
// spheres, contacts and forces bit for bit, over a sheared, compressed dense cloud whose
// contacts open and close (what a checkpoint restart relies on: the list is not saved).
TEST(NativeNeighbourList, ResultsDoNotDependOnWhenTheListIsRebuilt) {
  RveState a = dense_cloud();
  const int steps = 400;
  Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
  l(0, 1) = 0.05 / (steps * a.dt);
  l(2, 2) = -0.02 / (steps * a.dt);
  a.cell.set_vel_grad(l);
  RveState b = a;
  NeighbourList kept(0.5), fresh(0.5);
  std::size_t opened = 0;
  for (int k = 0; k < steps; ++k) {
    const std::size_t before = a.contacts.size();
    dem_step(a, kept, 0.2);
    fresh.invalidate();
    dem_step(b, fresh, 0.2);
    opened += before > a.contacts.size() ? before - a.contacts.size() : 0;
  }
  EXPECT_GT(opened, 50u);
  EXPECT_EQ(fresh.rebuilds(), steps);
  // The comparison needs both schedules: the kept list rebuilt more than once (the cloud
  // pushes itself apart: 44 rebuilds here) and kept over most steps.
  EXPECT_GE(kept.rebuilds(), 2);
  EXPECT_LT(kept.rebuilds(), steps / 4);
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
  };
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(same(a.spheres.pos.c[c], b.spheres.pos.c[c])) << "positions " << c;
    EXPECT_TRUE(same(a.spheres.vel.c[c], b.spheres.vel.c[c])) << "velocities " << c;
    EXPECT_TRUE(same(a.spheres.force.c[c], b.spheres.force.c[c])) << "forces " << c;
  }
}

// near_pairs (the new-contact search's short list): while it is offered, every pair of the
// list without a contact that overlaps is in it, also after contacts are removed; it is
// withdrawn once the spheres have moved too far.
TEST(NativeNeighbourList, NearPairsHoldEveryOverlapWithoutContact) {
  RveState s = dense_cloud();
  NeighbourList nl(0.5);
  nl.ensure(s);
  const auto overlaps = [&](std::uint32_t i, std::size_t p) {
    const double r = s.spheres.radius[i] + s.spheres.radius[nl.pair_j(p)];
    const Eigen::Vector3i c = nl.pair_cell(p).cast<int>();
    return (s.spheres.pos[nl.pair_j(p)] + s.cell.shift(c) - s.spheres.pos[i]).squaredNorm() < r * r;
  };
  // Every other overlapping pair becomes a contact.
  bool take = false;
  for (std::uint32_t i = 0; i < s.spheres.size(); ++i) {
    for (std::size_t p = nl.row_begin(i); p < nl.row_begin(i + 1); ++p) {
      if (!overlaps(i, p) || !(take = !take)) continue;
      s.contacts.add(i, nl.pair_j(p), nl.pair_cell(p));
      nl.contact_added(p);
    }
  }
  ASSERT_GT(s.contacts.size(), 50u);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r_min = *std::min_element(s.spheres.radius.begin(), s.spheres.radius.end());
  int offered = 0, withdrawn = 0;
  for (int k = 0; k < 40; ++k) {
    Eigen::Matrix3d df = Eigen::Matrix3d::Identity();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) df(a, b) += 1e-5 * u(rng);
    s.cell.hsize = df * s.cell.hsize;
    const double step = (k < 20 ? 0.002 : 0.02) * r_min;  // then faster: the list withdrawn
    for (std::size_t i = 0; i < s.spheres.size(); ++i) {
      s.spheres.pos.set(i, df * s.spheres.pos[i] + step * Vec3(u(rng), u(rng), u(rng)));
    }
    if (k % 5 == 0 && s.contacts.size() > 0) {  // a contact removed (as compute_forces does)
      nl.contact_removed(s.contacts, 0);
      s.contacts.swap_remove(0);
    }
    nl.ensure(s);
    std::size_t n_near = 0;
    const std::uint32_t* near = nl.near_pairs(s, &n_near);
    if (!near) {
      ++withdrawn;
      continue;
    }
    ++offered;
    std::set<std::size_t> listed;
    for (std::size_t q = 0; q < n_near; ++q) {
      listed.insert(near[2 * q + 1]);
      if (q > 0) {
        EXPECT_LT(near[2 * q - 1], near[2 * q + 1]);  // row order
      }
    }
    for (std::uint32_t i = 0; i < s.spheres.size(); ++i) {
      for (std::size_t p = nl.row_begin(i); p < nl.row_begin(i + 1); ++p) {
        if (nl.pair_in_contact(p) || !overlaps(i, p)) continue;
        EXPECT_EQ(listed.count(p), 1u) << "step " << k << " pair " << p;
      }
    }
  }
  EXPECT_GT(offered, 5);
  EXPECT_GT(withdrawn, 0);
}

}  // namespace
