// Tests of the half Verlet pair list: same pair set as an O(n²) search, CSR invariants, contact history carried by id pair across re-sorting/removal/insertion, identical
// lists for 1 and 2 threads, and the skin/2 rebuild criterion (Verlet, Phys. Rev. 159 (1967) 98).
#include "neighbor/pair_list.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <utility>

#include "core/diagnostics.h"
#include "neighbor/spatial_sort.h"
#include "neighbor/test_scenes.h"

namespace quarry {
namespace {

using IndexPair = std::pair<std::uint32_t, std::uint32_t>;

// The definition the list promises, by brute force: |xj − xi|² < ((Ri + Rj) + skin)².
std::set<IndexPair> brute_force_pairs(const ParticleStore& particles, double skin) {
  std::set<IndexPair> pairs;
  for (std::uint32_t i = 0; i < particles.size(); ++i)
    for (std::uint32_t j = i + 1; j < particles.size(); ++j) {
      const double reach = (particles.radius[i] + particles.radius[j]) + skin;  // m
      if (norm2(particles.position[j] - particles.position[i]) < reach * reach) pairs.insert({i, j});
    }
  return pairs;
}

std::set<IndexPair> listed_pairs(const PairList& list) {
  std::set<IndexPair> pairs;
  for (std::uint32_t i = 0; i + 1 < list.offsets.size(); ++i)
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) pairs.insert({i, list.partner[k]});
  return pairs;
}

void expect_csr_invariants(const PairList& list, std::size_t particle_count) {
  ASSERT_EQ(list.offsets.size(), particle_count + 1);
  EXPECT_EQ(list.offsets.front(), 0u);
  EXPECT_EQ(list.offsets.back(), list.size());
  EXPECT_EQ(list.tangential_displacement.size(), list.size());
  EXPECT_EQ(list.rolling_torque.size(), list.keep_rolling_history ? list.size() : 0);
  for (std::uint32_t i = 0; i < particle_count; ++i) {
    ASSERT_LE(list.offsets[i], list.offsets[i + 1]);
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      EXPECT_GT(list.partner[k], i);
      EXPECT_LT(list.partner[k], particle_count);
      if (k > list.offsets[i]) {
        EXPECT_LT(list.partner[k - 1], list.partner[k]);
      }
    }
  }
}

// A history value that encodes the ordered id pair (lower index first), to check carrying.
Vec3 history_of(ParticleId first, ParticleId second) {
  return {static_cast<double>(first), static_cast<double>(second), 1.0};
}

void stamp_history(const ParticleStore& particles, PairList& list) {
  for (std::uint32_t i = 0; i < particles.size(); ++i)
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      const ParticleId a = particles.id[i], b = particles.id[list.partner[k]];
      list.tangential_displacement[k] = history_of(a, b);
      list.rolling_torque[k] = 2.0 * history_of(a, b);
    }
}

// Checks every pair: history present iff the id pair was listed before (old_pairs, by ids),
// negated when the order of the pair flipped.
void expect_history_carried(const ParticleStore& particles, const PairList& list,
                            const std::set<std::pair<ParticleId, ParticleId>>& old_pairs,
                            std::size_t& carried, std::size_t& fresh) {
  for (std::uint32_t i = 0; i < particles.size(); ++i)
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      const ParticleId a = particles.id[i], b = particles.id[list.partner[k]];
      Vec3 expected{};
      if (old_pairs.count({a, b})) expected = history_of(a, b);
      if (old_pairs.count({b, a})) expected = -history_of(b, a);
      EXPECT_EQ(list.tangential_displacement[k], expected) << "ids " << a << ", " << b;
      EXPECT_EQ(list.rolling_torque[k], 2.0 * expected);
      ++(expected == Vec3{} ? fresh : carried);
    }
}

std::set<std::pair<ParticleId, ParticleId>> id_pairs(const ParticleStore& particles, const PairList& list) {
  std::set<std::pair<ParticleId, ParticleId>> pairs;
  for (const auto& [i, j] : listed_pairs(list)) pairs.insert({particles.id[i], particles.id[j]});
  return pairs;
}

TEST(PairList, SamePairsAsBruteForceForPolydisperseCloud) {
  // Radii 0.3–2 mm in a 3 cm cube: a wide size ratio, so small particles meet large ones
  // across more than their own cell width.
  const ParticleStore cloud = test_scenes::random_cloud(3000, 0.03, 0.3e-3, 2e-3, 21);
  for (double skin : {0.0, 0.1e-3, 1e-3}) {
    SCOPED_TRACE(skin);
    PairList list;
    build_pair_list(cloud, skin, list);
    expect_csr_invariants(list, cloud.size());
    const auto expected = brute_force_pairs(cloud, skin);
    EXPECT_GT(expected.size(), cloud.size() / 2);  // the test is not vacuous
    EXPECT_EQ(listed_pairs(list), expected);
    EXPECT_EQ(list.skin, skin);
    EXPECT_EQ(list.builds, 1u);
  }
}

TEST(PairList, SamePairsAsBruteForceWithAFarAwayParticleAndOnLatticeBed) {
  // The far particle forces coarse cells (the cell-count cap); pairs must not change.
  ParticleStore cloud = test_scenes::random_cloud(1500, 0.02, 0.5e-3, 1e-3, 22);
  cloud.add(9999, 0, 0, {-500.0, 20.0, 1e4}, {}, 1e-3, 2500.0, 0.0);
  PairList list;
  build_pair_list(cloud, 0.2e-3, list);
  expect_csr_invariants(list, cloud.size());
  EXPECT_EQ(listed_pairs(list), brute_force_pairs(cloud, 0.2e-3));

  const ParticleStore bed = test_scenes::lattice_bed(2000, 23);
  build_pair_list(bed, 0.2e-3, list);
  expect_csr_invariants(list, bed.size());
  EXPECT_EQ(listed_pairs(list), brute_force_pairs(bed, 0.2e-3));
  // Cubic lattice, spacing 2.1 mm, reach ≈ 2.2 mm: only the ~3 axial neighbours per particle.
  EXPECT_GT(list.size(), 2 * bed.size());
  EXPECT_LT(list.size(), 3 * bed.size());
}

// Pairs at the edge of reach to the last bit: the search takes candidates four at a time
// (pair_list.cpp), with lanes past a cell row's end and lanes of lower index masked out; each
// lane must decide |xj − xi|² < ((Ri + Rj) + skin)² exactly as the scalar expression does.
// Clusters of 1–12 particles around a centre, each at the reach (as computed in doubles) or one
// ulp either side of it, along random directions, indices shuffled; clusters far apart.
TEST(PairList, SamePairsAsBruteForceAtTheEdgeOfReachToTheLastBit) {
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), radius_of(0.5e-3, 1.5e-3);
  std::uniform_int_distribution<int> members(1, 12), side(-1, 1);
  const double skin = 0.2e-3;  // m
  struct Placed {
    Vec3 x;
    double radius;
    int centre;  // index in `placed` of its cluster's centre, before the shuffle (-1: a centre)
    int self;    // its index before the shuffle
  };
  std::vector<Placed> placed;
  for (int cluster = 0; cluster < 400; ++cluster) {
    const Vec3 centre{0.02 * (cluster % 20), 0.02 * (cluster / 20), 0.0};
    const double rc = radius_of(random);
    const int centre_index = static_cast<int>(placed.size());
    placed.push_back({centre, rc, -1, centre_index});
    for (int m = members(random); m > 0; --m) {
      Vec3 direction{unit(random), unit(random), unit(random)};
      direction = direction / std::sqrt(norm2(direction));
      const double r = radius_of(random);
      double distance = (rc + r) + skin;  // m: the reach, then an ulp either side
      const int s = side(random);
      if (s != 0) distance = std::nextafter(distance, s > 0 ? 1.0 : 0.0);
      placed.push_back({centre + distance * direction, r, centre_index,
                        static_cast<int>(placed.size())});
    }
  }
  std::shuffle(placed.begin(), placed.end(), random);
  ParticleStore particles;
  for (std::size_t k = 0; k < placed.size(); ++k)
    particles.add(k + 1, 0, 0, placed[k].x, {}, placed[k].radius, test_scenes::kDensity, 0.0);
  PairList list;
  build_pair_list(particles, skin, list);
  expect_csr_invariants(list, particles.size());
  const auto expected = brute_force_pairs(particles, skin);
  EXPECT_EQ(listed_pairs(list), expected);
  // Not vacuous: of the members, some are partners of their centre and some are not (the
  // brute force decides which; rounding of the direction moves a member by an ulp or two).
  std::vector<std::uint32_t> now(placed.size());
  for (std::uint32_t k = 0; k < placed.size(); ++k) now[placed[k].self] = k;
  std::size_t members_listed = 0, member_count = 0;
  for (const Placed& q : placed) {
    if (q.centre < 0) continue;
    const std::uint32_t a = now[q.centre], b = now[q.self];
    ++member_count;
    members_listed += expected.count({std::min(a, b), std::max(a, b)});
  }
  EXPECT_GT(members_listed, member_count / 5);
  EXPECT_LT(members_listed, member_count * 4 / 5);
}

// The same definition across periodic faces: |d|² < ((Ri + Rj) + skin)² with d the minimum
// image of xj − xi (Allen & Tildesley 2017, §1.6.3).
std::set<IndexPair> brute_force_periodic_pairs(const ParticleStore& particles, double skin,
                                               const PeriodicBox& box) {
  std::set<IndexPair> pairs;
  for (std::uint32_t i = 0; i < particles.size(); ++i)
    for (std::uint32_t j = i + 1; j < particles.size(); ++j) {
      const double reach = (particles.radius[i] + particles.radius[j]) + skin;  // m
      if (norm2(box.minimum_image(particles.position[j] - particles.position[i])) < reach * reach)
        pairs.insert({i, j});
    }
  return pairs;
}

// Periodic axes (issue #20): the cells wrap, so pairs across the faces are found once each, on
// one, two or three periodic axes, with a period of exactly three cells (the shortest the
// search allows), many cells, and with particles a little outside the period (they drift up to
// skin/2 past a face between rebuilds).
TEST(PairList, SamePairsAsBruteForceAcrossPeriodicFaces) {
  const double edge = 0.02, skin = 0.2e-3;  // m
  ParticleStore cloud = test_scenes::random_cloud(2000, edge, 0.3e-3, 1e-3, 31);
  // A few particles just outside the faces, as between rebuilds.
  cloud.position[0] = {-0.05e-3, 0.5 * edge, 0.5 * edge};
  cloud.position[1] = {edge + 0.05e-3, 0.5 * edge, 0.5 * edge + 1e-3};
  const Aabb domain{{0, 0, 0}, {edge, edge, edge}};
  std::size_t across = 0;
  for (const std::array<bool, 3> axes :
       {std::array<bool, 3>{true, false, false}, std::array<bool, 3>{true, true, false},
        std::array<bool, 3>{true, true, true}}) {
    PairList list;
    list.periodic = PeriodicBox::of(domain, axes);
    build_pair_list(cloud, skin, list);
    expect_csr_invariants(list, cloud.size());
    const auto expected = brute_force_periodic_pairs(cloud, skin, list.periodic);
    EXPECT_EQ(listed_pairs(list), expected);
    across += expected.size() - brute_force_pairs(cloud, skin).size();
  }
  EXPECT_GT(across, 100u);  // the faces were crossed
  // The shortest period: three cells of 2 R_max + skin on the periodic axis (and one cell wider
  // than the rest when L is not a whole number of cells).
  for (double period : {shortest_period(1e-3, skin), 1.1 * shortest_period(1e-3, skin)}) {
    ParticleStore narrow = test_scenes::random_cloud(400, 0.02, 0.3e-3, 1e-3, 32);
    for (Vec3& x : narrow.position) x.x *= period / 0.02;
    PairList list;
    list.periodic = PeriodicBox::of(Aabb{{0, 0, 0}, {period, 0.02, 0.02}}, {true, false, false});
    build_pair_list(narrow, skin, list);
    EXPECT_EQ(list.workspace.grid.cells_per_axis[0], 3u);
    EXPECT_EQ(listed_pairs(list), brute_force_periodic_pairs(narrow, skin, list.periodic));
  }
}

TEST(PeriodicBox, MinimumImageAndWrapLeaveOtherAxesAndInsidePointsUnchanged) {
  const PeriodicBox box = PeriodicBox::of(Aabb{{-1, 0, 0}, {2, 1, 1}}, {true, false, true});
  const Vec3 d{2.9, 0.123456789, -0.6};
  const Vec3 image = box.minimum_image(d);
  EXPECT_NEAR(image.x, -0.1, 1e-15);
  EXPECT_EQ(image.y, d.y);  // bit for bit
  EXPECT_NEAR(image.z, 0.4, 1e-15);
  const Vec3 inside{1.999, 0.3, 0.0};
  EXPECT_EQ(box.wrapped(inside), inside);
  const Vec3 wrapped = box.wrapped({2.25, 7.0, -0.25});
  EXPECT_NEAR(wrapped.x, -0.75, 1e-15);
  EXPECT_EQ(wrapped.y, 7.0);  // not periodic: left alone
  EXPECT_NEAR(wrapped.z, 0.75, 1e-15);
  EXPECT_EQ(box.wrapped({0, 0, 2.0}).z, 0.0);
  // A hair below min: x + L rounds to max itself, which is min again.
  EXPECT_EQ(box.wrapped({0, 0, -1e-300}).z, 0.0);
  const double below = std::nextafter(-1.0, -2.0);
  EXPECT_GE(box.wrapped({below, 0, 0}).x, -1.0);
  EXPECT_LT(box.wrapped({below, 0, 0}).x, 2.0);
}

TEST(PairList, EmptyAndSingleParticleAndZeroRadius) {
  ParticleStore particles;
  PairList list;
  build_pair_list(particles, 1e-3, list);
  EXPECT_EQ(list.size(), 0u);
  ASSERT_EQ(list.offsets.size(), 1u);
  particles.add(1, 0, 0, {0, 0, 0}, {}, 1e-3, 2500.0, 0.0);
  build_pair_list(particles, 1e-3, list);
  expect_csr_invariants(list, 1);
  EXPECT_EQ(list.size(), 0u);
  // Point particles with no skin cannot pair even when coincident: |d|² < 0 never holds.
  ParticleStore points;
  points.add(1, 0, 0, {0, 0, 0}, {}, 1.0, 2500.0, 0.0);
  points.add(2, 0, 0, {0, 0, 0}, {}, 1.0, 2500.0, 0.0);
  points.radius = {0.0, 0.0};
  build_pair_list(points, 0.0, list);
  EXPECT_EQ(list.size(), 0u);
}

TEST(PairList, HistorySurvivesARebuildWithoutChanges) {
  const ParticleStore bed = test_scenes::lattice_bed(3000, 31);
  PairList list;
  build_pair_list(bed, 0.2e-3, list);
  stamp_history(bed, list);
  const auto before = id_pairs(bed, list);
  build_pair_list(bed, 0.2e-3, list);
  std::size_t carried = 0, fresh = 0;
  expect_history_carried(bed, list, before, carried, fresh);
  EXPECT_EQ(carried, list.size());
  EXPECT_EQ(list.builds, 2u);
}

TEST(PairList, HistoryFollowsIdsThroughSpatialSortAndRandomPermutation) {
  ParticleStore cloud = test_scenes::random_cloud(2500, 0.025, 0.5e-3, 1.5e-3, 32);
  PairList list;
  build_pair_list(cloud, 0.3e-3, list);
  stamp_history(cloud, list);
  auto before = id_pairs(cloud, list);

  cloud.permute(spatial_order(cloud, 3.3e-3));
  EXPECT_TRUE(pair_list_needs_rebuild(cloud, list));  // the order changed
  build_pair_list(cloud, 0.3e-3, list);
  std::size_t carried = 0, fresh = 0;
  expect_history_carried(cloud, list, before, carried, fresh);
  EXPECT_EQ(carried, list.size());  // same positions: every pair is an old pair

  // A random permutation flips the order of about half the pairs (history changes sign).
  stamp_history(cloud, list);
  before = id_pairs(cloud, list);
  std::vector<std::size_t> order(cloud.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
  cloud.permute(order);
  build_pair_list(cloud, 0.3e-3, list);
  carried = fresh = 0;
  expect_history_carried(cloud, list, before, carried, fresh);
  EXPECT_EQ(carried, list.size());
}

// Removing particles from a list gives what a build for the remaining particles at the same
// positions gives (history carried by ids), bit for bit; the criterion still compares with
// the last build's positions.
// removed: which of the cloud's 2,500 particles go.
void expect_removal_matches_a_build_without_them(const std::vector<char>& removed) {
  ParticleStore cloud = test_scenes::random_cloud(2500, 0.025, 0.5e-3, 1.5e-3, 33);
  PairList list;
  list.keep_jkr_history = true;
  build_pair_list(cloud, 0.3e-3, list);
  stamp_history(cloud, list);
  for (std::size_t k = 0; k < list.size(); ++k) {
    list.normal_force[k] = 0.5 * static_cast<double>(k % 7);
    list.jkr_attached[k] = static_cast<std::uint8_t>(k % 3 == 0);
  }
  ASSERT_EQ(removed.size(), cloud.size());
  PairList rebuilt = list;
  remove_from_pair_list(list, removed);
  cloud.remove_flagged(removed);
  build_pair_list(cloud, 0.3e-3, rebuilt);
  expect_csr_invariants(list, cloud.size());
  EXPECT_EQ(list.offsets, rebuilt.offsets);
  EXPECT_EQ(list.partner, rebuilt.partner);
  EXPECT_EQ(list.tangential_displacement, rebuilt.tangential_displacement);
  EXPECT_EQ(list.rolling_torque, rebuilt.rolling_torque);
  EXPECT_EQ(list.jkr_attached, rebuilt.jkr_attached);
  EXPECT_EQ(list.reference_positions, rebuilt.reference_positions);
  EXPECT_EQ(list.ids_at_build, rebuilt.ids_at_build);
  EXPECT_EQ(list.builds, 2u);  // a new list for the force stage's plans
  // normal_force is history only where it is not zero: compare the pairs that carry one.
  for (std::size_t k = 0; k < list.size(); ++k) EXPECT_EQ(list.normal_force[k], rebuilt.normal_force[k]);
  EXPECT_FALSE(pair_list_needs_rebuild(cloud, list));
  cloud.position[5].x += 0.16e-3;  // more than half the skin from the last build's position
  EXPECT_TRUE(pair_list_needs_rebuild(cloud, list));
}

TEST(PairList, RemovingParticlesMatchesABuildWithoutThem) {
  std::vector<char> removed(2500, 0);
  for (std::size_t i = 0; i < removed.size(); i += 7) removed[i] = 1;  // the first and every 7th
  removed.back() = 1;                                                   // and the last
  expect_removal_matches_a_build_without_them(removed);
  // A few from the middle on (a hopper's outflow): the rows and pairs before the first removed
  // one stay in place, those after it move down, partners renumbered.
  std::fill(removed.begin(), removed.end(), 0);
  for (std::size_t i : {1250u, 1251u, 1400u, 2100u}) removed[i] = 1;
  expect_removal_matches_a_build_without_them(removed);
}

TEST(PairList, WithoutRollingHistoryOnlyTheTangentialHistoryIsKeptAndCarried) {
  ParticleStore cloud = test_scenes::random_cloud(2000, 0.02, 0.5e-3, 1.5e-3, 35);
  PairList list;
  list.keep_rolling_history = false;
  build_pair_list(cloud, 0.3e-3, list);
  expect_csr_invariants(list, cloud.size());
  EXPECT_TRUE(list.rolling_torque.empty());
  for (std::uint32_t i = 0; i < cloud.size(); ++i)
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k)
      list.tangential_displacement[k] = history_of(cloud.id[i], cloud.id[list.partner[k]]);
  const auto before = id_pairs(cloud, list);
  std::vector<std::size_t> order(cloud.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = order.size() - 1 - k;  // flips every pair
  cloud.permute(order);
  build_pair_list(cloud, 0.3e-3, list);
  EXPECT_TRUE(list.rolling_torque.empty());
  std::size_t carried = 0;
  for (std::uint32_t i = 0; i < cloud.size(); ++i)
    for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      const ParticleId a = cloud.id[i], b = cloud.id[list.partner[k]];
      ASSERT_TRUE(before.count({b, a}));
      EXPECT_EQ(list.tangential_displacement[k], -history_of(b, a));
      ++carried;
    }
  EXPECT_GT(carried, cloud.size() / 2);
}

TEST(PairList, HistoryOfSparseIdsIsCarried) {
  // Ids far apart (not 1..N): the id → index map falls back from a table to a hash.
  ParticleStore cloud = test_scenes::random_cloud(1500, 0.02, 0.5e-3, 1.5e-3, 36);
  for (auto& id : cloud.id) id = id * 1000003ull + (1ull << 40);
  PairList list;
  build_pair_list(cloud, 0.3e-3, list);
  stamp_history(cloud, list);
  const auto before = id_pairs(cloud, list);
  cloud.permute(spatial_order(cloud, 3.3e-3));
  build_pair_list(cloud, 0.3e-3, list);
  std::size_t carried = 0, fresh = 0;
  expect_history_carried(cloud, list, before, carried, fresh);
  EXPECT_EQ(carried, list.size());
}

TEST(PairList, HistoryAfterRemovalAndInsertion) {
  ParticleStore cloud = test_scenes::random_cloud(2500, 0.025, 0.5e-3, 1.5e-3, 33);
  PairList list;
  build_pair_list(cloud, 0.3e-3, list);
  stamp_history(cloud, list);
  const auto before = id_pairs(cloud, list);

  std::vector<char> remove(cloud.size(), 0);
  for (std::size_t i = 0; i < cloud.size(); i += 7) remove[i] = 1;
  cloud.remove_flagged(remove);
  const ParticleStore extra = test_scenes::random_cloud(400, 0.025, 0.5e-3, 1.5e-3, 34, 100000);
  for (std::size_t k = 0; k < extra.size(); ++k)
    cloud.add(extra.id[k], 0, 0, extra.position[k], {}, extra.radius[k], 2500.0, 0.0);
  EXPECT_TRUE(pair_list_needs_rebuild(cloud, list));
  build_pair_list(cloud, 0.3e-3, list);
  expect_csr_invariants(list, cloud.size());
  EXPECT_EQ(listed_pairs(list), brute_force_pairs(cloud, 0.3e-3));
  std::size_t carried = 0, fresh = 0;
  expect_history_carried(cloud, list, before, carried, fresh);
  EXPECT_GT(carried, 0u);  // surviving old pairs kept their history
  EXPECT_GT(fresh, 0u);    // pairs with inserted particles start from zero
}

TEST(PairList, IdenticalForOneAndTwoThreads) {
  // Big enough for every parallel path (pair search, both counting sorts, id remapping).
  ParticleStore bed = test_scenes::lattice_bed(40000, 41);
  std::vector<std::size_t> order(bed.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = order.size() - 1 - k;
  const int threads_before = omp_get_max_threads();
  PairList lists[2];
  for (int t = 0; t < 2; ++t) {
    omp_set_num_threads(t + 1);
    ParticleStore particles = bed;
    build_pair_list(particles, 0.2e-3, lists[t]);
    stamp_history(particles, lists[t]);
    particles.permute(order);
    build_pair_list(particles, 0.2e-3, lists[t]);
  }
  omp_set_num_threads(threads_before);
  EXPECT_GT(lists[0].size(), 40000u);
  EXPECT_EQ(lists[0].offsets, lists[1].offsets);
  EXPECT_EQ(lists[0].partner, lists[1].partner);
  EXPECT_EQ(lists[0].tangential_displacement, lists[1].tangential_displacement);
  EXPECT_EQ(lists[0].rolling_torque, lists[1].rolling_torque);
}

TEST(PairList, RebuildCriterionIsHalfTheSkinForPairsAndTheSkinAgainstMovingSurfaces) {
  ParticleStore bed = test_scenes::lattice_bed(500, 51);
  const double skin = 0.2e-3;  // m
  PairList list;
  EXPECT_TRUE(pair_list_needs_rebuild(bed, list));  // never built
  build_pair_list(bed, skin, list);
  EXPECT_FALSE(pair_list_needs_rebuild(bed, list));
  bed.position[17].x += 0.49 * skin;
  EXPECT_FALSE(pair_list_needs_rebuild(bed, list));
  // A moving surface spends the rest of the whole skin: 0.49 + 0.5 < 1, 0.49 + 0.52 > 1.
  EXPECT_FALSE(pair_list_needs_rebuild(bed, list, 0.5 * skin));
  EXPECT_TRUE(pair_list_needs_rebuild(bed, list, 0.52 * skin));
  bed.position[17].x += 0.02 * skin;
  EXPECT_TRUE(pair_list_needs_rebuild(bed, list));
  bed.position[17] = list.reference_positions[17];
  EXPECT_FALSE(pair_list_needs_rebuild(bed, list));
  bed.position[3].z = std::nan("");
  EXPECT_TRUE(pair_list_needs_rebuild(bed, list));
  try {
    build_pair_list(bed, skin, list);
    ADD_FAILURE() << "a NaN position must stop the build";
  } catch (const PhysicsError& error) {
    EXPECT_NE(std::string(error.what()).find("particle id 4 "), std::string::npos) << error.what();
  }
  EXPECT_EQ(list.builds, 1u);  // the failed build left the previous list intact
  EXPECT_EQ(list.offsets.size(), bed.size() + 1);
  bed.position[3] = list.reference_positions[3];
  bed.add(10000, 0, 0, {0, 0, 0}, {}, 1e-3, 2500.0, 0.0);
  EXPECT_TRUE(pair_list_needs_rebuild(bed, list));  // count changed
}

TEST(PairList, ListStaysCompleteWhileEveryParticleMovesLessThanHalfTheSkin) {
  // Verlet's guarantee: if no particle moved more than skin/2, every pair now touching
  // (|xi − xj| < Ri + Rj) was within Ri + Rj + skin at the build, hence is listed.
  ParticleStore cloud = test_scenes::random_cloud(2000, 0.02, 0.5e-3, 1e-3, 61);
  const double skin = 0.4e-3;  // m
  PairList list;
  build_pair_list(cloud, skin, list);
  const auto listed = listed_pairs(list);
  std::mt19937_64 random(62);
  std::normal_distribution<double> normal;
  for (auto& x : cloud.position) {
    const Vec3 direction = normalized(Vec3{normal(random), normal(random), normal(random)});
    x += 0.4999 * skin * direction;
  }
  ASSERT_FALSE(pair_list_needs_rebuild(cloud, list));
  const auto touching = brute_force_pairs(cloud, 0.0);
  EXPECT_GT(touching.size(), 100u);
  for (const auto& pair : touching) EXPECT_TRUE(listed.count(pair));
}

}  // namespace
}  // namespace quarry
