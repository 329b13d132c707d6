// The Delassus operator from the band of A^-1 (chainDelassusOperator) against
// the dense H A^-1 H^T and against the CHOLMOD block solve, on random chains
// and on the system matrix of the packed coil (stiff axially, light).
#include "endovascular_sim/contact/delassus.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "endovascular_sim/mechanics/device_model.h"
#include "endovascular_sim/mechanics/implicit_euler.h"
#include "endovascular_sim/scene/scene_file.h"
#include "endovascular_sim/sim/simulation.h"
#include "test_helpers.h"

namespace evsim {
namespace {

using test::randomSpdChain;

Row12 randomRow(std::mt19937* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Row12 h;
  for (int k = 0; k < 12; ++k) h(k) = n(*rng);
  return h;
}

/// H (rows x free DOFs) of the rows, dense.
MatX denseH(const std::vector<ContactRow>& rows, int n) {
  MatX H = MatX::Zero(static_cast<int>(rows.size()), n);
  for (size_t j = 0; j < rows.size(); ++j)
    for (int part = 0; part < rows[j].parts; ++part)
      for (int k = 0; k < 12; ++k) {
        const int dof = rows[j].offset[part] + k;
        if (dof >= 0 && dof < n) H(j, dof) += rows[j].h[part](k);
      }
  return H;
}

/// Rows of every kind the contact solver makes: several on one element, on
/// the first and last free elements, one whose first node is held, one with
/// both held (no column), self contacts with their parts far apart, adjacent
/// and on the same element.
std::vector<ContactRow> rowsOfEveryKind(int free_blocks, std::mt19937* rng) {
  std::uniform_int_distribution<int> element(0, free_blocks - 2);
  std::vector<ContactRow> rows;
  auto single = [&](int e) {
    ContactRow r;
    r.offset[0] = 6 * e;
    r.h[0] = randomRow(rng);
    rows.push_back(r);
  };
  auto pair = [&](int e1, int e2) {
    ContactRow r;
    r.parts = 2;
    r.offset[0] = 6 * e1;
    r.offset[1] = 6 * e2;
    r.h[0] = randomRow(rng);
    r.h[1] = randomRow(rng);
    rows.push_back(r);
  };
  for (int k = 0; k < 20; ++k) single(element(*rng));
  single(0);
  single(free_blocks - 2);
  single(5);
  single(5);
  single(-1);  // first node held
  single(-2);  // both nodes held: a zero row
  pair(3, free_blocks - 3);
  pair(free_blocks - 4, 2);
  pair(7, 8);
  pair(9, 9);
  pair(-1, 11);
  return rows;
}

TEST(ChainInverse, BandMatchesTheDenseInverse) {
  std::mt19937 rng(3);
  const ChainMatrix A = randomSpdChain(30, &rng);
  for (int first : {0, 6}) {
    ChainInverse inverse;
    ASSERT_TRUE(inverse.compute(A, first));
    const int nb = A.numBlocks() - first;
    ASSERT_EQ(inverse.numBlocks(), nb);
    const MatX S = A.toDense().bottomRightCorner(6 * nb, 6 * nb).inverse();
    for (int i = 0; i < nb; ++i) {
      EXPECT_LT((inverse.diagonal(i) - S.block<6, 6>(6 * i, 6 * i)).norm(), 1e-12 * S.norm());
      if (i + 1 < nb) {
        EXPECT_LT((inverse.subdiagonal(i) - S.block<6, 6>(6 * i + 6, 6 * i)).norm(),
                  1e-12 * S.norm());
      }
    }
    // A solve from the same factorisation.
    const VecX b = VecX::Random(6 * nb);
    VecX x = b;
    inverse.solveInPlace(&x);
    EXPECT_LT((x - S * b).norm(), 1e-12 * S.norm() * b.norm());
    // A column far from the band, carried down from the diagonal.
    const Vec6 g = Vec6::Random();
    const int j = nb - 2;
    Vec6 v = inverse.diagonal(j) * g;
    for (int i = j - 1; i >= 0; --i) {
      v = inverse.propagateDown(i, v);
      EXPECT_LT((v - S.block<6, 6>(6 * i, 6 * j) * g).norm(), 1e-12 * S.norm() * g.norm()) << i;
    }
  }
}

TEST(ChainInverse, ReportsAnIndefiniteMatrix) {
  std::mt19937 rng(4);
  ChainMatrix A = randomSpdChain(8, &rng);
  A.diag[5](1, 1) = -200.0;
  ChainInverse inverse;
  EXPECT_FALSE(inverse.compute(A, 0));
  EXPECT_TRUE(inverse.compute(A, 6));  // the indefinite block is held
}

/// After a loop of the contact solver, some rows change (a plane updated)
/// and new ones come (new contacts); the update copies the entries between
/// unchanged rows and computes the rest: with few fresh rows their columns
/// alone (two sweeps), with many one sweep with every column. Either must
/// equal the dense operator of the new rows, and using a stale entry must
/// show.
TEST(ChainDelassus, AnUpdateAfterSomeRowsChangedMatchesTheDenseOperator) {
  std::mt19937 rng(17);
  const ChainMatrix A = randomSpdChain(40, &rng);
  const int first = 4, nb = 36, n = 6 * nb;
  ChainInverse inverse;
  ASSERT_TRUE(inverse.compute(A, first));
  const std::vector<ContactRow> before = rowsOfEveryKind(nb, &rng);
  MatX W_before;
  chainDelassusOperator(inverse, before, &W_before);
  const std::vector<ContactRow> more = rowsOfEveryKind(nb, &rng);
  // Few fresh rows (a single and a self contact changed, 6 new: 8 of 37),
  // then many (16 changed and 6 new), each by both paths of the update.
  const std::vector<std::vector<int>> changes = {
      {17, 28}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 21, 26, 28, 30}};
  for (const DelassusUpdate path : {DelassusUpdate::kFreshColumns, DelassusUpdate::kSweep})
    for (const std::vector<int>& change : changes) {
      std::vector<ContactRow> after = before;
      std::vector<char> changed(before.size(), 0);
      for (int r : change) {
        for (int part = 0; part < after[r].parts; ++part) after[r].h[part] = randomRow(&rng);
        changed[r] = 1;
      }
      after.insert(after.end(), more.begin(), more.begin() + 6);  // new rows
      MatX W = W_before;
      updateChainDelassusOperator(inverse, after, changed, &W, path);
      const MatX H = denseH(after, n);
      const MatX dense = H * A.toDense().bottomRightCorner(n, n).llt().solve(H.transpose());
      EXPECT_LT((W - dense).norm(), 1e-12 * dense.norm())
          << change.size() << " changed, path " << static_cast<int>(path);
      EXPECT_EQ(W, W.transpose());
      changed[17] = 0;  // a changed row taken as unchanged: its old entries stay
      MatX stale = W_before;
      updateChainDelassusOperator(inverse, after, changed, &stale, path);
      EXPECT_GT((stale - dense).norm(), 1e-3 * dense.norm());
    }
}

TEST(ChainDelassus, MatchesDenseAndBlockSolveForEveryKindOfRow) {
  std::mt19937 rng(11);
  const ChainMatrix A = randomSpdChain(40, &rng);
  const int first = 4, nb = 36, n = 6 * nb;
  const std::vector<ContactRow> rows = rowsOfEveryKind(nb, &rng);
  ChainInverse inverse;
  ASSERT_TRUE(inverse.compute(A, first));
  MatX W;
  chainDelassusOperator(inverse, rows, &W);
  const MatX H = denseH(rows, n);
  const MatX dense = H * A.toDense().bottomRightCorner(n, n).llt().solve(H.transpose());
  EXPECT_LT((W - dense).norm(), 1e-12 * dense.norm());
  EXPECT_EQ(W, W.transpose());                    // exactly symmetric: each pair computed once
  EXPECT_EQ(W.row(rows.size() - 6).norm(), 0.0);  // the row with both nodes held

  SparseCholesky chol;
  ASSERT_TRUE(test::factorChain(A, first, &chol));
  MatX Y, W_block;
  delassusOperator(chol, rows, &Y, &W_block);
  EXPECT_LT((W - W_block).norm(), 1e-12 * dense.norm());
  // H^T lambda, solved: the block solve's Y lambda.
  const VecX lambda = VecX::Random(static_cast<int>(rows.size()));
  VecX x = contactForce(n, rows, lambda);
  EXPECT_LT((x - H.transpose() * lambda).norm(), 1e-14 * x.norm());
  chol.solveInPlace(&x);
  EXPECT_LT((x - Y * lambda).norm(), 1e-12 * x.norm());
}

TEST(ChainDelassus, ColumnsOneAtATimeMatchTheDenseOperator) {
  // The status method's columns on demand (ChainColumns): each column and
  // the diagonal against H A^-1 H^T formed densely, for rows of every kind,
  // written through a row map as the contact solver does (rows of the
  // device among those of the problem).
  std::mt19937 rng(12);
  const ChainMatrix A = randomSpdChain(40, &rng);
  const int first = 4, nb = 36, n = 6 * nb;
  const std::vector<ContactRow> rows = rowsOfEveryKind(nb, &rng);
  const int c = static_cast<int>(rows.size());
  ChainInverse inverse;
  ASSERT_TRUE(inverse.compute(A, first));
  const MatX H = denseH(rows, n);
  const MatX dense = H * A.toDense().bottomRightCorner(n, n).llt().solve(H.transpose());
  std::vector<int> to(c);
  for (int i = 0; i < c; ++i) to[i] = 2 * i + 1;  // every other row of a problem twice as large
  const ChainColumns columns(inverse, rows, to);
  for (int j = 0; j < c; ++j) {
    VecX out = VecX::Zero(2 * c + 1);
    columns.addColumn(j, out.data());
    VecX column(c);
    for (int i = 0; i < c; ++i) column(i) = out(to[i]);
    EXPECT_LT((column - dense.col(j)).norm(), 1e-12 * dense.norm()) << "column " << j;
    EXPECT_EQ(out(0), 0.0);  // nothing outside the map
  }
  VecX diagonal = VecX::Zero(2 * c + 1);
  columns.addDiagonal(diagonal.data());
  for (int i = 0; i < c; ++i)
    EXPECT_NEAR(diagonal(to[i]), dense(i, i), 1e-12 * dense.norm()) << "row " << i;
}

/// The coil of `aneurysm_packed` with `inserted` [m] out of the introducer
/// (light elements, axially far stiffer than their mass term), in free
/// space after three steps; rows at every third element's sample points.
struct CoilSystem {
  SceneModel model;
  SimData data;
  std::vector<ContactRow> rows;
  int n{0};  // free DOFs
};

CoilSystem packedCoilSystem(double inserted) {
  SceneSpec spec = loadSceneFile(resolveScenePath("aneurysm_packed"));
  spec.vessels.present = false;
  spec.devices[0].inserted_length = inserted;
  CoilSystem c;
  c.model = buildSceneModel(spec);
  c.data = makeData(c.model);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(step(c.model, &c.data), StepStatus::kOk);
  const int first = c.data.workspaces[0].first_free_node;
  c.n = 6 * (c.model.devices[0].num_nodes - first);
  for (const SamplePoint& s : c.model.samples[0]) {
    if (s.element + 1 < first || s.element % 3 != 0) continue;
    ContactRow r;
    r.offset[0] = 6 * (s.element - first);
    r.h[0] = contactRow(c.model.devices[0], c.data.devices[0], s, Vec3::Random().normalized());
    c.rows.push_back(r);
  }
  return c;
}

/// W of the coil's rows from the band of A^-1 and from the block solve;
/// false when A is not positive definite.
bool bothOperators(CoilSystem* c, MatX* W_chain, MatX* W_block) {
  DeviceWorkspace& ws = c->data.workspaces[0];
  ChainInverse inverse;
  if (!inverse.compute(ws.system, ws.first_free_node)) return false;
  chainDelassusOperator(inverse, c->rows, W_chain);
  MatX Y;
  delassusOperator(ws.factor, c->rows, &Y, W_block);
  return true;
}

TEST(ChainDelassus, MatchesALongDoubleSolveOnThePackedCoilsMatrix) {
  // 8 cm out (966 free DOFs): the reference is a dense Cholesky in long
  // double. Measured: 6.0e-12 relative (the block solve: 1.2e-11).
  CoilSystem c = packedCoilSystem(0.08);
  ASSERT_GE(c.rows.size(), 50u);
  MatX W, W_block;
  ASSERT_TRUE(bothOperators(&c, &W, &W_block));
  const DeviceWorkspace& ws = c.data.workspaces[0];
  using MatL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const MatL A = ws.system.toDense().bottomRightCorner(c.n, c.n).cast<long double>();
  const MatL H = denseH(c.rows, c.n).cast<long double>();
  const MatX reference = (H * A.llt().solve(H.transpose())).cast<double>();
  EXPECT_LT((W - reference).norm(), 1e-10 * reference.norm());
  EXPECT_LT((W_block - reference).norm(), 1e-10 * reference.norm());
}

TEST(ChainDelassus, MatchesTheBlockSolveOnTheWholePackedCoil) {
  CoilSystem c = packedCoilSystem(0.28);  // 560 free elements
  ASSERT_GE(c.rows.size(), 150u);
  MatX W, W_block;
  ASSERT_TRUE(bothOperators(&c, &W, &W_block));
  EXPECT_LT((W - W_block).norm(), 1e-10 * W_block.norm()) << c.rows.size() << " rows";
}

/// A 0.36 mm nitinol wire of `elements` elements over `length` [m], all but
/// 2 mm out of its introducer, bent by sin(rate i) [cm] at node i, with the
/// free motion's factor of its matrix.
struct BentWire {
  DeviceModel model;
  DeviceState state;
  DeviceWorkspace ws;
};

BentWire bentNitinolWire(double length, int elements, double rate) {
  BeamSection sec;
  sec.young_modulus = 60e9;
  sec.shear_modulus = 60e9 / 2.66;
  sec.outer_radius = 1.78e-4;
  sec.density = 6450;
  BentWire w;
  w.model = buildDeviceModel(straightDeviceSpec("wire", sec, length, elements));
  Introducer intro;
  w.state = placeDevice(w.model, intro, w.model.length - 0.002, 0.0);
  for (int i = 0; i < w.model.num_nodes; ++i) w.state.position[i].y() += 0.01 * std::sin(rate * i);
  computeFreeMotion(w.model, intro, Vec3::Zero(), 1e-3, w.state, &w.ws);
  return w;
}

TEST(ChainDelassus, MatchesALongDoubleSolveOnAStiffNitinolWire) {
  // The benchmarks' wire: 200 nitinol elements of 2 mm, bent; cond(A) is
  // 8.7e12. Measured: 1.9e-11 relative (the block solve: 1.2e-11). Forming
  // L_i^T as D^-1 A_{i,i+1} with an explicit D^-1 gave 8.6e-10.
  BentWire wire = bentNitinolWire(0.4, 200, 0.03);
  const DeviceModel& model = wire.model;
  const DeviceState& state = wire.state;
  const DeviceWorkspace& ws = wire.ws;
  std::mt19937 rng(100);  // 100 rows at random points, normals across the wire
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int first = ws.first_free_node, n = ws.factor.size();
  std::vector<ContactRow> rows;
  for (int j = 0; j < 100; ++j) {
    const SamplePoint p{first + static_cast<int>(u(rng) * (model.num_nodes - 2 - first)), u(rng),
                        1.78e-4};
    const Vec3 t = state.rotation[p.element] * Vec3::UnitX();
    const Vec3 normal = Eigen::AngleAxisd(2 * M_PI * u(rng), t) * t.unitOrthogonal();
    ContactRow cr;
    cr.offset[0] = 6 * (p.element - first);
    cr.h[0] = contactRow(model, state, p, normal);
    rows.push_back(cr);
  }
  ChainInverse inverse;
  ASSERT_TRUE(inverse.compute(ws.system, first));
  MatX W, Y, W_block;
  chainDelassusOperator(inverse, rows, &W);
  delassusOperator(ws.factor, rows, &Y, &W_block);
  using MatL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const MatL A = ws.system.toDense().bottomRightCorner(n, n).cast<long double>();
  const MatL H = denseH(rows, n).cast<long double>();
  const MatX ref = (H * A.llt().solve(H.transpose())).cast<double>();
  EXPECT_LT((W - ref).norm(), 1e-10 * ref.norm());
  EXPECT_LT((W_block - ref).norm(), 1e-10 * ref.norm());
}

TEST(TrailingDelassus, SolvesOnlyBelowTheRowsAndCarriesTheCorrectionUp) {
  // Rows on the distal third of a bent wire only: W and A^-1 H^T l from the
  // trailing solve against a dense long double Cholesky of the whole A.
  BentWire wire = bentNitinolWire(0.2, 90, 0.05);
  const DeviceModel& model = wire.model;
  const DeviceState& state = wire.state;
  const DeviceWorkspace& ws = wire.ws;
  const int first = ws.first_free_node, n = ws.factor.size();
  std::vector<ContactRow> rows;
  for (int e = 60; e + 1 < model.num_nodes; e += 4) {
    const Vec3 t = state.rotation[e] * Vec3::UnitX();
    ContactRow cr;
    cr.offset[0] = 6 * (e - first);
    cr.h[0] = contactRow(model, state, SamplePoint{e, 0.5, 1.78e-4}, t.unitOrthogonal());
    rows.push_back(cr);
  }
  TrailingSolve Y;
  MatX W;
  delassusOperator(ws.factor, rows, &Y, &W);
  EXPECT_EQ(Y.first_block, 60 - first);
  EXPECT_EQ(Y.Y.rows(), n - 6 * Y.first_block);
  const VecX l = VecX::LinSpaced(static_cast<int>(rows.size()), 0.1, 1.0);
  VecX dq = VecX::Zero(n);
  addSolveTimes(ws.factor, Y, l, dq);
  using MatL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  using VecL = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  const MatL A = ws.system.toDense().bottomRightCorner(n, n).cast<long double>();
  const MatL H = denseH(rows, n).cast<long double>();
  const Eigen::LLT<MatL> llt(A);
  const MatX W_ref = (H * llt.solve(H.transpose())).cast<double>();
  const VecX dq_ref = llt.solve(VecL(H.transpose() * l.cast<long double>())).cast<double>();
  EXPECT_LT((W - W_ref).norm(), 1e-10 * W_ref.norm());
  EXPECT_LT((dq - dq_ref).norm(), 1e-10 * dq_ref.norm());
  // The proximal blocks, carried up the chain, are not zero: the wire's
  // whole free part moves.
  EXPECT_GT(dq.head(6 * Y.first_block).norm(), 1e-3 * dq.norm());
}

}  // namespace
}  // namespace evsim
