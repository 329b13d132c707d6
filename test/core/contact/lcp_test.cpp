// LCP solvers against Siconos numerics (the independent oracle).
#include "endovascular_sim/contact/lcp.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "endovascular_sim/contact/contact_solver.h"
#include "endovascular_sim/sim/simulation.h"
#include "siconos_oracle.h"

namespace evsim {
namespace {

struct Lcp {
  MatX W;
  VecX q;
};

/// W = B B^T with B c x rank (rank < c: rank-deficient, redundant contacts),
/// plus a diagonal shift for definite cases; q with mostly negative entries.
Lcp randomLcp(int c, int rank, double shift, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  MatX B(c, rank);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = n(*rng);
  Lcp l{B * B.transpose() / rank + shift * MatX::Identity(c, c), VecX(c)};
  for (int i = 0; i < c; ++i) l.q(i) = n(*rng) - 0.5;
  return l;
}

/// A contact LCP as the step makes it, with more contacts than degrees of
/// freedom: W = B B^T (B = H L^-T, c x dofs) and q = B (u_f - u*) + s, s >= 0:
/// the constraints admit the configuration u* (a feasible QP), so the LCP
/// is solvable although W is singular.
Lcp redundantContactLcp(int c, int dofs, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  MatX B(c, dofs);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = n(*rng);
  VecX du(dofs), s(c);
  for (int i = 0; i < dofs; ++i) du(i) = n(*rng);
  for (int i = 0; i < c; ++i) s(i) = u(*rng) < 0.5 ? 0.0 : u(*rng);
  return {B * B.transpose(), B * du + s};
}

TEST(Lcp, SmallAnalyticProblem) {
  //  w1 = 2 z1 + z2 - 1,  w2 = z1 + 2 z2 + 1  ->  z = (1/2, 0), w = (0, 3/2)
  MatX W(2, 2);
  W << 2, 1, 1, 2;
  const VecX q = (VecX(2) << -1, 1).finished();
  for (auto s : {LcpSolver::kStatusMethod, LcpSolver::kLemke, LcpSolver::kPgs}) {
    LcpOptions o;
    o.solver = s;
    VecX z;
    ASSERT_EQ(solveLcp(W, q, o, &z), LcpStatus::kSolved) << lcpSolverName(s);
    EXPECT_NEAR(z(0), 0.5, 1e-10) << lcpSolverName(s);
    EXPECT_NEAR(z(1), 0.0, 1e-10) << lcpSolverName(s);
  }
}

/// Solves with the status method (from the empty set and from every
/// violated row, the paper's start) and Lemke, checks each solved to a
/// residual of 1e-10, and returns their solutions.
std::vector<VecX> solveWithOurs(const Lcp& l) {
  std::vector<VecX> out;
  for (int variant = 0; variant < 3; ++variant) {
    LcpOptions o;
    o.solver = variant == 2 ? LcpSolver::kLemke : LcpSolver::kStatusMethod;
    o.start_from_violated = variant == 1;
    VecX z;
    LcpStats st;
    EXPECT_EQ(solveLcp(l.W, l.q, o, &z, &st), LcpStatus::kSolved) << variant;
    // Recomputed here: the status method reports its own residual.
    EXPECT_LE(lcpResidual(l.W, l.q, z), 1e-10) << variant << " c=" << l.q.size();
    EXPECT_NEAR(st.residual, lcpResidual(l.W, l.q, z), 1e-14) << variant;
    out.push_back(z);
  }
  return out;
}

class AgainstSiconos : public ::testing::TestWithParam<int> {};

TEST_P(AgainstSiconos, PositiveDefiniteSolutionsAgree) {
  const int c = GetParam();
  std::mt19937 rng(100 + c);
  const Lcp l = randomLcp(c, c, 0.05, &rng);
  VecX ref;
  ASSERT_EQ(test::siconosLcp(l.W, l.q, SICONOS_LCP_LEMKE, 1e-14, &ref), 0);
  for (const VecX& z : solveWithOurs(l))
    EXPECT_LT((z - ref).norm(), 1e-8 * std::max(1.0, ref.norm())) << "c=" << c;
}

INSTANTIATE_TEST_SUITE_P(Sizes, AgainstSiconos, ::testing::Values(1, 2, 5, 10, 40, 100, 300));

class RankDeficientAgainstSiconos : public ::testing::TestWithParam<int> {};

TEST_P(RankDeficientAgainstSiconos, GapsAgree) {
  const int c = GetParam();
  std::mt19937 rng(200 + c);
  const Lcp l = redundantContactLcp(c, std::max(1, c / 2), &rng);  // half the contacts redundant
  VecX ref;
  ASSERT_EQ(test::siconosLcp(l.W, l.q, SICONOS_LCP_LEMKE, 1e-14, &ref), 0);
  const VecX w_ref = l.W * ref + l.q;
  for (const VecX& z : solveWithOurs(l))  // z is not unique, w is
    EXPECT_LT((l.W * z + l.q - w_ref).norm(), 1e-8 * std::max(1.0, l.q.norm())) << "c=" << c;
}

INSTANTIATE_TEST_SUITE_P(Sizes, RankDeficientAgainstSiconos,
                         ::testing::Values(2, 5, 10, 40, 100, 300));

TEST(Lcp, WarmStartedStatusMethodFindsTheSameGapsInFewerPivots) {
  // Redundant contact sets (300 rows on 150 DOFs), as in the activation
  // loop: the next loop's LCP is this one with q moved a little; it is
  // started from this one's forces.
  for (int seed : {1, 2, 3}) {
    std::mt19937 rng(700 + seed);
    const Lcp l = redundantContactLcp(300, 150, &rng);
    VecX cold, warm;
    LcpStats cold_stats, warm_stats;
    ASSERT_EQ(solveLcp(l.W, l.q, {}, &cold, &cold_stats), LcpStatus::kSolved);
    // q + W d = B (du + B^T d) + s: the moved problem stays feasible.
    std::normal_distribution<double> n(0.0, 0.01 * cold.norm() / std::sqrt(300.0));
    VecX d(300);
    for (int i = 0; i < d.size(); ++i) d(i) = n(rng);
    const VecX q = l.q + l.W * d;
    VecX reference;
    ASSERT_EQ(test::siconosLcp(l.W, q, SICONOS_LCP_LEMKE, 1e-14, &reference), 0);
    cold.resize(0);  // (an empty z: a cold start)
    ASSERT_EQ(solveLcp(l.W, q, {}, &cold, &cold_stats), LcpStatus::kSolved);
    solveLcp(l.W, l.q, {}, &warm);  // this loop's forces ...
    ASSERT_EQ(solveLcp(l.W, q, {}, &warm, &warm_stats), LcpStatus::kSolved);  // ... start the next
    const VecX w_ref = l.W * reference + q;
    EXPECT_LT((l.W * warm + q - w_ref).norm(), 1e-8 * q.norm()) << seed;
    EXPECT_LT((l.W * cold + q - w_ref).norm(), 1e-8 * q.norm()) << seed;
    EXPECT_LE(lcpResidual(l.W, q, warm), 1e-10) << seed;
    EXPECT_LT(warm_stats.iterations, cold_stats.iterations / 2) << seed;
    std::printf("[ metric   ] warm start, seed %d: %d pivots against %d cold\n", seed,
                warm_stats.iterations, cold_stats.iterations);
  }
}

/// The next activation loop's problem after `first` (W = B B^T, q = B du
/// + s): `changed` of B's rows re-formed at random (their points moved) and
/// `added` new rows appended, the rest kept with their entries of W to the
/// bit (as the loop keeps them: contact.row_turn); still feasible.
Lcp nextLoopLcp(const Lcp& first, const MatX& B0, const VecX& du, const VecX& s0, int changed,
                int added, std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int c0 = static_cast<int>(B0.rows()), dofs = static_cast<int>(B0.cols());
  const int c = c0 + added;
  MatX B(c, dofs);
  B.topRows(c0) = B0;
  std::vector<char> fresh(c, 0);
  for (int k = 0; k < changed; ++k) fresh[static_cast<int>(u(*rng) * c0)] = 1;
  for (int i = c0; i < c; ++i) fresh[i] = 1;
  for (int i = 0; i < c; ++i)
    if (fresh[i])
      for (int j = 0; j < dofs; ++j) B(i, j) = n(*rng);
  VecX s(c);
  s.head(c0) = s0;
  for (int i = c0; i < c; ++i) s(i) = u(*rng) < 0.5 ? 0.0 : u(*rng);
  Lcp next{B * B.transpose(), B * du + s};
  for (int j = 0; j < c0; ++j)
    for (int i = 0; i < c0; ++i)
      if (!fresh[i] && !fresh[j]) next.W(i, j) = first.W(i, j);
  return next;
}

TEST(Lcp, TheNextLoopsLcpStartsFromTheLastFactorForTheSameAnswer) {
  // The activation loop's next loop keeps most rows (and W's entries among
  // them), re-forms a few and adds a few: its status method starts from the
  // factor the last solve kept, its rows whose entries changed removed,
  // instead of factorising its warm start afresh. The gaps against
  // Siconos' Lemke, and against the same solve from a fresh factor; with
  // half of the rows changed it factorises afresh.
  for (int seed : {1, 2, 3}) {
    std::mt19937 rng(1300 + seed);
    std::normal_distribution<double> n(0.0, 1.0);
    MatX B0(300, 200);
    for (int i = 0; i < B0.size(); ++i) B0.data()[i] = n(rng);
    VecX du(200), s(300);
    for (int i = 0; i < 200; ++i) du(i) = n(rng);
    for (int i = 0; i < 300; ++i) s(i) = std::max(0.0, n(rng));
    const Lcp first{B0 * B0.transpose(), B0 * du + s};
    for (const int changed : {5, 150}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", rows changed " + std::to_string(changed));
      const Lcp next = nextLoopLcp(first, B0, du, s, changed, 8, &rng);
      VecX reference;
      ASSERT_EQ(test::siconosLcp(next.W, next.q, SICONOS_LCP_LEMKE, 1e-14, &reference), 0);
      const VecX w_ref = next.W * reference + next.q;
      const LcpOptions o;  // (z of size c: the warm start)
      VecX forces;
      LcpWorkspace kept;  // what the first solve leaves for the next
      ASSERT_EQ(solveLcp(first.W, first.q, {}, &forces, nullptr, &kept), LcpStatus::kSolved);
      LcpWorkspace after_first = kept;  // (a copy holds the same factor)
      VecX resumed = VecX::Zero(308);
      resumed.head(300) = forces;
      LcpStats st;
      ASSERT_EQ(solveLcp(next.W, next.q, o, &resumed, &st, &kept), LcpStatus::kSolved);
      EXPECT_EQ(st.resumed, changed == 5);
      // The same warm start from a fresh factor: another solve in between
      // keeps its own.
      VecX other = VecX::Ones(1);
      solveLcp(MatX::Identity(1, 1), -VecX::Ones(1), {}, &other, nullptr, &after_first);
      VecX fresh = VecX::Zero(308);
      fresh.head(300) = forces;
      LcpStats fresh_st;
      ASSERT_EQ(solveLcp(next.W, next.q, o, &fresh, &fresh_st, &after_first), LcpStatus::kSolved);
      EXPECT_FALSE(fresh_st.resumed);
      // Without a workspace nothing is kept: a fresh factor.
      VecX alone = VecX::Zero(308);
      alone.head(300) = forces;
      LcpStats alone_st;
      ASSERT_EQ(solveLcp(next.W, next.q, o, &alone, &alone_st), LcpStatus::kSolved);
      EXPECT_FALSE(alone_st.resumed);
      EXPECT_LT((next.W * resumed + next.q - w_ref).norm(), 1e-8 * next.q.norm());
      EXPECT_LT((next.W * fresh + next.q - w_ref).norm(), 1e-8 * next.q.norm());
      EXPECT_LE(lcpResidual(next.W, next.q, resumed), 1e-10);
      std::printf(
          "[ metric   ] seed %d, %d rows changed and 8 added: %s, gaps %.2e from Lemke's "
          "(fresh factor %.2e), %d pivots (fresh %d)\n",
          seed, changed, st.resumed ? "resumed" : "factorised afresh",
          (next.W * resumed + next.q - w_ref).norm() / next.q.norm(),
          (next.W * fresh + next.q - w_ref).norm() / next.q.norm(), st.iterations,
          fresh_st.iterations);
    }
  }
}

TEST(Lcp, AWarmStartWithManyWrongForcesSwapsThemWithoutEvaluatingEveryGapEachTime) {
  // A packed coil's first loop: the last step's forces start it, and some
  // 40 % of them sit on the wrong rows (its turns' forces move to
  // neighbouring element pairs). The status method swaps them pivot by
  // pivot; every gap is evaluated only when no watched row is violated.
  // The gaps against Siconos' Lemke; the pivots' path against the status
  // method from a cold start (same answer).
  for (int seed : {1, 2, 3}) {
    std::mt19937 rng(1100 + seed);
    const Lcp l = redundantContactLcp(300, 200, &rng);
    VecX reference;
    ASSERT_EQ(test::siconosLcp(l.W, l.q, SICONOS_LCP_LEMKE, 1e-14, &reference), 0);
    // The warm start: the answer's forces, 40 % of them moved to rows
    // without one (and the other way round).
    std::vector<int> with, without;
    for (int i = 0; i < 300; ++i) (reference(i) > 0.0 ? with : without).push_back(i);
    std::shuffle(with.begin(), with.end(), rng);
    std::shuffle(without.begin(), without.end(), rng);
    VecX warm = reference;
    const size_t moved = std::min(with.size() * 2 / 5, without.size());
    for (size_t k = 0; k < moved; ++k) std::swap(warm(with[k]), warm(without[k]));
    LcpStats st;
    ASSERT_EQ(solveLcp(l.W, l.q, {}, &warm, &st), LcpStatus::kSolved) << seed;
    const VecX w_ref = l.W * reference + l.q;
    EXPECT_LT((l.W * warm + l.q - w_ref).norm(), 1e-8 * l.q.norm()) << seed;
    EXPECT_LE(lcpResidual(l.W, l.q, warm), 1e-10) << seed;
    EXPECT_GE(st.activations, static_cast<int>(moved) / 2) << seed;
    EXPECT_LT(st.gap_sweeps, st.activations / 2) << seed;
    std::printf(
        "[ metric   ] %zu forces on wrong rows, seed %d: %d activations, %d deactivations, %d "
        "evaluations of every gap\n",
        moved, seed, st.activations, st.deactivations, st.gap_sweeps);
  }
}

/// W handed out column by column, counting the columns read.
class CountedColumns final : public ColumnOperator {
 public:
  explicit CountedColumns(const MatX& W) : W_(W), read_(W.cols(), 0) {}
  int size() const override { return static_cast<int>(W_.rows()); }
  Eigen::Map<const VecX> column(int j) override {
    read_[j] = 1;
    return Eigen::Map<const VecX>(W_.col(j).data(), W_.rows());
  }
  double maxDiagonal() override { return W_.diagonal().maxCoeff(); }
  int read() const { return static_cast<int>(std::count(read_.begin(), read_.end(), 1)); }

 private:
  const MatX& W_;
  std::vector<char> read_;
};

TEST(Lcp, TheStatusMethodOnColumnsOnDemandReadsFewColumnsForTheSameAnswer) {
  // A contact LCP of many rows and few forces (400 rows on 60 DOFs, most
  // gaps open), as a wire along a catheter's lumen makes: the answer on
  // columns given one at a time is the dense one's to round-off, against
  // Siconos' Lemke, and only the columns of rows that were active are read.
  for (int seed : {1, 2, 3}) {
    std::mt19937 rng(900 + seed);
    Lcp l = redundantContactLcp(400, 60, &rng);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 400; ++i)
      if (u(rng) < 0.85) l.q(i) = std::abs(l.q(i)) + 1.0;  // open: never active
    VecX reference, dense, lazy;
    ASSERT_EQ(test::siconosLcp(l.W, l.q, SICONOS_LCP_LEMKE, 1e-14, &reference), 0);
    LcpStats dense_stats, lazy_stats;
    ASSERT_EQ(solveLcp(l.W, l.q, {}, &dense, &dense_stats), LcpStatus::kSolved);
    CountedColumns columns(l.W);
    ASSERT_EQ(solveLcp(columns, l.q, {}, &lazy, &lazy_stats), LcpStatus::kSolved);
    const VecX w_ref = l.W * reference + l.q;
    EXPECT_LT((l.W * lazy + l.q - w_ref).norm(), 1e-8 * l.q.norm()) << seed;
    EXPECT_LT((lazy - dense).norm(), 1e-12 * dense.norm()) << seed;
    EXPECT_EQ(lazy_stats.iterations, dense_stats.iterations) << seed;
    const int active = static_cast<int>((lazy.array() > 0.0).count());
    EXPECT_LE(columns.read(), lazy_stats.activations) << seed;
    EXPECT_LT(columns.read(), 400 / 4) << seed;
    std::printf("[ metric   ] columns on demand, seed %d: %d of 400 columns read, %d forces\n",
                seed, columns.read(), active);
  }
}

// Two contacts that push a body in opposite directions by the same matrix
// row, both violated: w1 = z1 - z2 - 1 and w2 = z2 - z1 - 1 sum to -2, so no
// z >= 0 makes both gaps non-negative (a wire squeezed between two walls
// closer than its diameter). W is positive semi-definite, so Lemke's ray
// proves it (Siconos' Lemke fails on it too): infeasible, never solved. The
// status method answers the regularised problem and says, by its status and
// its residual, that the answer is no solution of this one.
TEST(Lcp, AnInfeasibleProblemIsReportedAsSuch) {
  MatX W(2, 2);
  W << 1.0, -1.0, -1.0, 1.0;
  const VecX q = VecX::Constant(2, -1.0);
  VecX reference;
  EXPECT_NE(test::siconosLcp(W, q, SICONOS_LCP_LEMKE, 1e-12, &reference), 0);
  LcpOptions o;
  o.solver = LcpSolver::kLemke;
  VecX z;
  LcpStats st;
  EXPECT_EQ(solveLcp(W, q, o, &z, &st), LcpStatus::kInfeasible);
  o.solver = LcpSolver::kStatusMethod;
  z.resize(0);
  EXPECT_EQ(solveLcp(W, q, o, &z, &st), LcpStatus::kUnsolved);  // an answer of W + eps I only
  std::printf("[ metric   ] infeasible LCP: the status method's residual %.3g\n", st.residual);
  EXPECT_GT(st.residual, 0.5);  // the sum of the gaps is -2 whatever z
}

TEST(Lcp, PgsConvergesToTheSameSolutionSlowly) {
  std::mt19937 rng(5);
  const Lcp l = randomLcp(40, 40, 0.5, &rng);
  VecX exact, z;
  ASSERT_EQ(solveLcp(l.W, l.q, {LcpSolver::kLemke}, &exact), LcpStatus::kSolved);
  LcpOptions few{LcpSolver::kPgs, 1e-14, 5, 0.0}, many{LcpSolver::kPgs, 1e-14, 5000, 0.0};
  LcpStats st_few, st_many;
  solveLcp(l.W, l.q, few, &z, &st_few);
  const double err_few = (z - exact).norm();
  solveLcp(l.W, l.q, many, &z, &st_many);
  EXPECT_LT((z - exact).norm(), 1e-8 * exact.norm());
  EXPECT_GT(err_few, 100 * (z - exact).norm());  // accuracy costs iterations
}

TEST(Lcp, AnEmptyProblemIsSolvedByEverySolver) {
  for (auto s : {LcpSolver::kStatusMethod, LcpSolver::kPgs, LcpSolver::kLemke}) {
    VecX z = VecX::Ones(3);
    EXPECT_EQ(solveLcp(MatX(0, 0), VecX(0), {s}, &z), LcpStatus::kSolved) << lcpSolverName(s);
    EXPECT_EQ(z.size(), 0) << lcpSolverName(s);
  }
}

TEST(Lcp, LemkeSolvesAWireDroppingOntoAFloor) {
  // Real steps' LCPs (contact_test's wire on a floor, 63 and 64 contacts):
  // every gap is the same to 1e-6 (the whole wire falls g dt^2), so the
  // ratio tests tie, and W is ill-conditioned (cond 1.7e8 and 8e8). Without
  // a lexicographic tie-break Lemke ended on a ray; its answer's residual is
  // cond(W) eps, not zero. The gaps w = W z + q are unique: they are checked
  // against Siconos.
  for (const char* file : {"floor_equal_gaps.lcp", "floor_ill_conditioned.lcp"}) {
    const LcpRecord r = readLcpRecord(std::string(EVSIM_TEST_DATA_DIR) + "/" + file);
    EXPECT_NEAR(r.q.minCoeff(), r.q.maxCoeff(), 1e-6 * std::abs(r.q.maxCoeff())) << file;
    LcpOptions o;
    o.solver = LcpSolver::kLemke;
    VecX z;
    ASSERT_EQ(solveLcp(r.W, r.q, o, &z), LcpStatus::kSolved) << file;
    EXPECT_LE(lcpResidual(r.W, r.q, z), 1e-8) << file;
    VecX ref;
    ASSERT_EQ(test::siconosLcp(r.W, r.q, SICONOS_LCP_LEMKE, 1e-12, &ref), 0) << file;
    EXPECT_LT((r.W * z - r.W * ref).norm(), 1e-7 * r.q.norm()) << file;
  }
}

TEST(Lcp, StatusMethodNeverCyclesOnDegenerateProblems) {
  // Many identical contacts (the same wall seen by several points): W has
  // rank 1 and ties everywhere.
  const int c = 50;
  MatX W = MatX::Ones(c, c);
  VecX q = VecX::Constant(c, -1.0);
  VecX z;
  LcpStats st;
  EXPECT_EQ(solveLcp(W, q, {LcpSolver::kStatusMethod}, &z, &st), LcpStatus::kSolved);
  EXPECT_LE(lcpResidual(W, q, z), 1e-10);
  EXPECT_NEAR(z.sum(), 1.0, 1e-9);  // the total force is determined
}

}  // namespace
}  // namespace evsim

// LCPs taken from real steps of the shipped scenes, against Siconos.
namespace evsim {
namespace {

TEST(Lcp, SceneLcpsAgreeWithSiconos) {
  int compared = 0, largest = 0, beyond_siconos = 0;
  struct Source {
    const char* scene;
    int steps, quota;  // every `every`-th step's LCP of at least min_rows rows, up to the quota
    int every, min_rows;
  };
  // large_step (40 ms steps, the wire looped in the arch): LCPs of 150-370 rows.
  for (const Source& src : {Source{"carotid", 6000, 30, 10, 3}, Source{"aneurysm", 3000, 30, 10, 3},
                            Source{"large_step", 150, 20, 1, 150}}) {
    const char* name = src.scene;
    const SceneModel m = loadScene(name);
    SimData d = makeData(m);
    d.record_lcp = true;
    for (int k = 0, taken = 0; k < src.steps && taken < src.quota; ++k) {
      ASSERT_EQ(step(m, &d), StepStatus::kOk) << d.last_error;
      if (d.lcp.q.size() < src.min_rows || k % src.every) continue;
      const LcpRecord& r = d.lcp;
      const int c = static_cast<int>(r.q.size());
      VecX ref;
      // Siconos to its own error 1e-12: Lemke, else its pivoting solver.
      const bool oracle = test::siconosLcp(r.W, r.q, SICONOS_LCP_LEMKE, 1e-12, &ref) == 0 ||
                          test::siconosLcp(r.W, r.q, SICONOS_LCP_PIVOT, 1e-12, &ref) == 0;
      if (!oracle) {
        // Beyond the c <= 400 Siconos may fail (a 673-row LCP of
        // large_step: Lemke's and the pivot solver's errors 0.035). The
        // status method must still solve it; our Lemke may fail, but must
        // say so rather than return a wrong answer.
        ASSERT_GT(c, 400) << name << " step " << k << ": Siconos failed";
        VecX z;
        LcpOptions o;
        ASSERT_EQ(solveLcp(r.W, r.q, o, &z), LcpStatus::kSolved) << name << " step " << k;
        const double residual = lcpResidual(r.W, r.q, z);
        EXPECT_LE(residual, 1e-10) << name << " step " << k;
        o.solver = LcpSolver::kLemke;
        if (solveLcp(r.W, r.q, o, &z) == LcpStatus::kSolved) {
          EXPECT_LE(lcpResidual(r.W, r.q, z), 1e-10) << name << " step " << k << " Lemke";
        }
        std::printf(
            "[ metric   ] %s step %d: Siconos fails on c = %d; status method residual %.3g\n", name,
            k, c, residual);
        ++beyond_siconos;
        continue;
      }
      // The Delassus operator of a contact set may be singular: compare the
      // gaps w, which are unique, and the total force along each normal set.
      for (int variant = 0; variant < 3; ++variant) {
        LcpOptions o;
        o.solver = variant == 2 ? LcpSolver::kLemke : LcpSolver::kStatusMethod;
        o.start_from_violated = variant == 1;  // the paper's start
        VecX z;
        ASSERT_EQ(solveLcp(r.W, r.q, o, &z), LcpStatus::kSolved) << name << " step " << k;
        EXPECT_LE(lcpResidual(r.W, r.q, z), 1e-10) << name << " step " << k << " " << variant;
        EXPECT_LT((r.W * z - r.W * ref).norm(), 1e-8 * std::max(r.q.norm(), 1e-12))
            << name << " step " << k;
      }
      largest = std::max(largest, c);
      ++compared;
      ++taken;
    }
  }
  std::printf(
      "[ metric   ] %d scene LCPs compared with Siconos, largest c = %d; %d larger where "
      "Siconos fails\n",
      compared, largest, beyond_siconos);
  EXPECT_GE(compared, 60);
  EXPECT_GE(largest, 300);
}

TEST(Lcp, DumpFormatRoundTrips) {
  std::mt19937 rng(1);
  const Lcp l = randomLcp(7, 7, 0.1, &rng);
  LcpRecord r{l.W, l.q, VecX::Random(7), VecX()};
  const std::string path = ::testing::TempDir() + "/evsim_roundtrip.lcp";
  ASSERT_TRUE(writeLcpRecord(r, path));
  const LcpRecord back = readLcpRecord(path);
  EXPECT_EQ((back.W - r.W).norm(), 0.0);
  EXPECT_EQ((back.q - r.q).norm(), 0.0);
  EXPECT_EQ((back.z - r.z).norm(), 0.0);
}

}  // namespace
}  // namespace evsim
