// The linear problem of one activation loop (the paper's section 2.2): the
// loop's free motion with the wall's curvature term (A + C), the rows of H
// and q linearised at the loop's x, the Delassus operator W = H A^-1 H^T
// per device (from the band of A^-1 or a block solve), and the correction
// x = x_f + A^-1 H^T lambda. Called by resolveContacts (contact_solver.cpp)
// through activation_loop.h.
#include <algorithm>
#include <cmath>

#include "activation_loop.h"
#include "contact_workspace_kept.h"
#include "endovascular_sim/contact/wall_curvature.h"
#include "endovascular_sim/mechanics/elasticity.h"

namespace evsim::activation {
namespace {

/// Orthonormal tangents of a contact plane: t1 along the device axis (its
/// part across n), t2 = n x t1.
std::array<Vec3, 2> tangentBasis(const Vec3& n, const Vec3& axis) {
  Vec3 t1 = axis - axis.dot(n) * n;
  if (t1.norm() < 1e-6) t1 = n.unitOrthogonal();
  t1.normalize();
  return {t1, n.cross(t1)};
}

/// True when two rows of H are the same (parts, offsets, coefficients).
bool sameRow(const ContactRow& a, const ContactRow& b) {
  if (a.parts != b.parts) return false;
  for (int k = 0; k < a.parts; ++k)
    if (a.offset[k] != b.offset[k] || a.h[k] != b.h[k]) return false;
  return true;
}
/// C (contact/wall_curvature.h) of the wall contacts with a force, per
/// device; A + C into the workspace's `curved_system`. (*curved)[d] says
/// whether device d has such a term (else A alone). A + C is factorised
/// where W will likely need it: for a device with at least
/// kChainCurvedBandRows contacts, as its band (ws.inverse, whose block
/// LDL^T also serves the solves), else as a chain factor (`curved`; the
/// band follows from it if fromBand asks). (*band)[d] is updated; a band
/// of A + C left from before becomes kNone.
void factorWallCurvature(const ContactProblem& pb, const std::vector<Contact>& contacts,
                         const std::vector<DeviceState>& x, std::vector<CurvatureTerm>* C,
                         std::vector<char>* curved, std::vector<Band>* band) {
  const auto& devices = *pb.devices;
  auto& ws = *pb.workspaces;
  const auto& samples = *pb.samples;
  const size_t nd = devices.size();
  C->resize(nd);
  for (CurvatureTerm& c : *C) {  // the storage kept from the last loop
    c.element.clear();
    c.block.clear();
  }
  curved->assign(nd, 0);
  for (Band& b : *band)
    if (b == Band::kOfCurved) b = Band::kNone;
  std::vector<int> rows(nd, 0);  // contacts with a part on each device (its rows of H)
  for (const Contact& ct : contacts) {
    ++rows[ct.device];
    if (ct.other_device >= 0 && ct.other_device != ct.device) ++rows[ct.other_device];
  }
  for (const Contact& ct : contacts) {
    // (wall contacts only; the lumen's curvature: lumen_curvature.cpp)
    if (ct.other_device >= 0 || !(ct.force > 0.0)) continue;
    const int d = ct.device;
    const SamplePoint& s = samples[d][ct.sample];
    const int e = s.element;
    if (e + 1 < ws[d].first_free_node) continue;  // both nodes held
    std::array<Vec3, 2> t;
    const Eigen::Matrix2d S =
        wallCurvature(*pb.surface, ct.point, ct.normal, s.radius, pb.motion, &t);
    if (S.isZero(0.0)) continue;
    Eigen::Matrix<double, 2, 12> R;
    R.row(0) = contactRow(devices[d], x[d], s, t[0]);
    R.row(1) = contactRow(devices[d], x[d], s, t[1]);
    (*C)[d].element.push_back(e);
    (*C)[d].block.push_back(ct.force * R.transpose() * S * R);
  }
  for (size_t d = 0; d < nd; ++d) {
    DeviceWorkspace& w = ws[d];
    const int n = w.factor.size();
    if ((*C)[d].empty() || n == 0) continue;
    // A + C from its first block that C changes (block m: before it, A + C
    // is A, and its factor is A's: copied, not eliminated again; on a wire
    // touching the wall near its tip only, most of the chain); the blocks
    // before m - 1 are never read. Storage kept across loops and steps.
    ChainMatrix& Ac = w.curved_system;
    const int blocks = w.system.numBlocks(), first = w.first_free_node;
    int m = blocks;
    for (const int e : (*C)[d].element) m = std::min(m, e >= first ? e : e + 1);
    Ac.resize(blocks);
    for (int i = std::max(first, m - 1); i < blocks; ++i) {
      Ac.diag[i] = w.system.diag[i];
      if (i + 1 < blocks) Ac.upper[i] = w.system.upper[i];
    }
    for (size_t k = 0; k < (*C)[d].element.size(); ++k) {
      const int e = (*C)[d].element[k];
      const Mat12& Ce = (*C)[d].block[k];
      if (e >= first) {
        Ac.diag[e] += Ce.topLeftCorner<6, 6>();
        Ac.upper[e] += Ce.topRightCorner<6, 6>();
      }
      Ac.diag[e + 1] += Ce.bottomRightCorner<6, 6>();
    }
    // (C is positive semi-definite, so this should not fail; if it does, A.)
    if (rows[d] >= kChainCurvedBandRows) {
      const bool ok = w.inverse.compute(Ac, first, &w.factor, m - first);
      (*band)[d] = ok ? Band::kOfCurved : Band::kNone;
      if (ok) {
        (*curved)[d] = 1;
        continue;
      }
    }
    (*curved)[d] = w.curved.factorize(Ac, first, &w.factor, m - first) ? 1 : 0;
  }
}

/// The QP step's free motion about the iterate dq for the devices with a
/// curvature term: (*dq_step)[d] = (A + C)^-1 (A dq_free + C dq_k), and
/// their factor that of A + C. Others keep A and dq_free. The solve uses
/// the band's block LDL^T where it holds A + C, else the device's factor
/// of A + C. Over the free nodes only (dq_free and dq_k taken as zero on
/// the held ones), as dq_free + (A + C)^-1 C (dq_k - dq_free): C has a few
/// blocks, so the right-hand side is zero before the first of them (the
/// forward pass starts there) and A's product is not formed.
void curvedFreeMotion(const ContactProblem& pb, const std::vector<CurvatureTerm>& C,
                      const std::vector<char>& curved, const std::vector<Band>& band,
                      const std::vector<VecX>& dq, std::vector<VecX>* dq_step,
                      std::vector<const ChainFactor*>* factor) {
  auto& ws = *pb.workspaces;
  for (size_t d = 0; d < curved.size(); ++d) {
    if (!curved[d]) continue;
    DeviceWorkspace& w = ws[d];
    const int n = w.factor.size(), first = w.first_free_node;
    VecX& step = (*dq_step)[d];  // dq_free on entry
    VecX rhs = VecX::Zero(n);    // C (dq_k - dq_free) on the free nodes
    int first_nonzero = n / 6;
    for (size_t k = 0; k < C[d].element.size(); ++k) {
      const int e = C[d].element[k];
      Vec12 towards = dq[d].segment<12>(6 * e) - step.segment<12>(6 * e);
      if (e < first) towards.head<6>().setZero();  // a held node
      const Vec12 y = C[d].block[k] * towards;
      if (e >= first) rhs.segment<6>(6 * (e - first)) += y.head<6>();
      rhs.segment<6>(6 * (e + 1 - first)) += y.tail<6>();
      first_nonzero = std::min(first_nonzero, std::max(e - first, 0));
    }
    (*factor)[d] = band[d] == Band::kOfCurved ? &w.inverse.factor() : &w.curved;
    (*factor)[d]->solveInPlace(&rhs, first_nonzero);
    step.tail(n) += rhs;
  }
}
}  // namespace

void prepareFreeMotion(const ContactProblem& pb, const ContactOptions& o, int loop, LoopState* s,
                       LoopSystem* sys) {
  auto& ws = *pb.workspaces;
  const size_t nd = ws.size();
  sys->factor.resize(nd);
  sys->dq_step = s->dq_free;
  for (size_t d = 0; d < nd; ++d) sys->factor[d] = &ws[d].factor;
  // The QP is taken about dq_k: x_t in the first loop, later the last
  // iterate (wall_curvature.h); the lumen's curvature rows too.
  if (loop == 1) {
    s->anchor.resize(nd);
    for (size_t d = 0; d < nd; ++d) s->anchor[d].setZero(s->dq[d].size());
  } else {
    s->anchor = s->dq;
  }
  if (!o.wall_curvature || !pb.surface) return;
  // C from the last loop's forces for the first curvature_loops loops;
  // later loops keep it (and the band of (A + C)^-1): at the answer
  // dq = dq_k, so C shapes the path, not the step's solution.
  if (loop <= o.curvature_loops) {
    const std::vector<Band> before = s->band;
    factorWallCurvature(pb, *s->contacts, s->x, &s->curvature, &s->curved, &s->band);
    for (size_t d = 0; d < nd; ++d) {
      if (s->band[d] != before[d] || s->band[d] == Band::kOfCurved) {
        s->last_rows[d].clear();  // W of another matrix: nothing to reuse
        s->last_W[d].size = 0;
      }
    }
  }
  curvedFreeMotion(pb, s->curvature, s->curved, s->band, s->anchor, &sys->dq_step, &sys->factor);
}

namespace {

/// Part `part` of contact i's normal row at x (sign: +1 for its own point,
/// -1 for a pair's other point): the row formed by an earlier loop where
/// its point and normal are the same and its element's node tangents
/// turned by at most `turn` [rad] since, else formed at x and kept.
Row12 normalRow(const ContactProblem& pb, const std::vector<DeviceState>& x, int device,
                const SamplePoint& sp, const Vec3& n, double sign, int part, double turn,
                FormedRow* formed) {
  const DeviceState& xd = x[device];
  const Vec3 t0 = xd.rotation[sp.element] * Vec3::UnitX();
  const Vec3 t1 = xd.rotation[sp.element + 1] * Vec3::UnitX();
  if (formed->parts > part && formed->normal == n && formed->element[part] == sp.element &&
      formed->xi[part] == sp.xi && (t0 - formed->tangent[part][0]).squaredNorm() <= turn * turn &&
      (t1 - formed->tangent[part][1]).squaredNorm() <= turn * turn)
    return formed->h[part];
  if (part == 0) formed->normal = n;
  formed->parts = part + 1;
  formed->element[part] = sp.element;
  formed->xi[part] = sp.xi;
  formed->tangent[part] = {t0, t1};
  formed->h[part] = sign * contactRow((*pb.devices)[device], xd, sp, n);
  return formed->h[part];
}

/// The rows of H and q at x, as parts per device.
void formRows(const ContactProblem& pb, const ContactOptions& o, LoopState& s, LoopSystem* sys,
              std::vector<std::vector<RowPart>>* parts) {
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
  const auto& samples = *pb.samples;
  const std::vector<DeviceState>& x = s.x;
  const int dim = pb.effects.friction ? 3 : 1;
  // The rows are linearised at x, the configuration of the last loop (x_f
  // in the first): g(x_f + A^-1 H^T lambda) ~ g(x) + H (x_f - x) + W lambda.
  // Linearised at x_f throughout, a loop whose correction moves points far
  // from x_f (a pre-shaped tip squeezed into a narrow lumen springs open by
  // millimetres in the free motion) keeps stale rows and stops converging.
  // Adds the part's row of H at x; returns its share of H (x_f - x).
  auto addRow = [&](int row, int device, const SamplePoint& sp, const Row12& h) {
    (*parts)[device].push_back({row, sp.element, h});
    const int at = 6 * sp.element;
    return h.dot(sys->dq_step[device].segment<12>(at) - s.dq[device].segment<12>(at));
  };
  auto addPart = [&](int row, int device, const SamplePoint& sp, const Vec3& n, double sign) {
    return addRow(row, device, sp, sign * contactRow(devices[device], x[device], sp, n));
  };
  // Rows are kept where that keeps W's entries: on a device whose last
  // loop's W came from the band, kept while the band stays (deviceOperator);
  // elsewhere W is formed whole again, and a row formed at x costs nothing
  // more than a kept one.
  s.formed.resize(sys->c);
  auto turn = [&](int device) { return s.last_rows[device].empty() ? 0.0 : o.row_turn; };
  for (int i = 0; i < sys->c; ++i) {
    Contact& ct = (*s.contacts)[i];
    const SamplePoint& sp = contactPointOf(ct, samples);
    const Vec3 p = samplePosition(devices[ct.device], x[ct.device], sp);
    const int row = dim * i;
    FormedRow* formed = &s.formed[i];
    sys->q(row) =
        addRow(row, ct.device, sp,
               normalRow(pb, x, ct.device, sp, ct.normal, 1.0, 0, turn(ct.device), formed));
    const SamplePoint* so = nullptr;
    Vec3 po = Vec3::Zero();
    if (ct.other_device < 0) {
      sys->q(row) += ct.normal.dot(p - ct.point);
    } else {
      so = &ct.other;
      po = samplePosition(devices[ct.other_device], x[ct.other_device], *so);
      sys->q(row) += ct.normal.dot(p - po) - ct.separation +
                     addRow(row, ct.other_device, *so,
                            normalRow(pb, x, ct.other_device, *so, ct.normal, -1.0, 1,
                                      turn(ct.other_device), formed));
    }
    if (!pb.effects.friction) continue;
    // Tangent rows: q is the slip over the step (relative to the other
    // point for pairs).
    sys->tangents[i] = tangentBasis(ct.normal, sampleTangent(x[ct.device], sp));
    Vec3 slip = p - samplePosition(devices[ct.device], start[ct.device], sp);
    if (so) slip -= po - samplePosition(devices[ct.other_device], start[ct.other_device], *so);
    sys->mu(i) = so ? std::sqrt(sp.friction * so->friction) : sp.friction;
    for (int k = 0; k < 2; ++k) {
      const Vec3& t = sys->tangents[i][k];
      sys->q(row + 1 + k) = t.dot(slip) + addPart(row + 1 + k, ct.device, sp, t, 1.0);
      if (so) sys->q(row + 1 + k) += addPart(row + 1 + k, ct.other_device, *so, t, -1.0);
    }
  }
}

/// Device d's rows of H (a self contact's two parts in one row), in the
/// order of their first part; (*of_device) their rows in the problem.
void deviceRows(const std::vector<RowPart>& parts, int first_free_node, int m,
                std::vector<int>* column_of_row, std::vector<int>* of_device,
                std::vector<ContactRow>* device_rows) {
  column_of_row->assign(m, -1);  // row -> its column in this device's operator
  of_device->reserve(parts.size());
  device_rows->reserve(parts.size());
  for (const RowPart& pt : parts) {
    const Row12& h = pt.h;
    const int offset = 6 * (pt.element - first_free_node);
    int& column = (*column_of_row)[pt.row];
    if (column < 0) {
      column = static_cast<int>(device_rows->size());
      of_device->push_back(pt.row);
      ContactRow row;
      row.offset[0] = offset;
      row.h[0] = h;
      device_rows->push_back(row);
    } else {  // a self contact: its second part on the same device
      ContactRow& row = (*device_rows)[column];
      row.offset[1] = offset;
      row.h[1] = h;
      row.parts = 2;
    }
  }
}

/// The band of (A + C)^-1 whenever C changed, of A once a step, from the
/// factor this loop steps with.
void ensureBand(const ContactProblem& pb, size_t d, LoopState* s, const LoopSystem* sys) {
  const Band wanted = s->curved[d] ? Band::kOfCurved : Band::kOfA;
  if (s->band[d] == wanted) return;
  (*pb.workspaces)[d].inverse.computeFrom(*sys->factor[d]);
  s->band[d] = wanted;
  s->last_rows[d].clear();  // nothing to reuse
  s->last_W[d].size = 0;
}

/// Whether device d's operator comes from the band of A^-1 rather than
/// from the block solve, by their cost in column-blocks (one right-hand
/// side through one node of the chain's solve): the block solve c (n - f)
/// for c rows whose first node is f of n; the band 4 n where it is not yet
/// there for this loop's matrix (ensureBand), and its sweep 24 c. On the
/// 200-element wire of the benchmarks the solve costs 0.021 us a
/// column-block, the band from the factor 17.2 us, the sweep 0.5 us a row
/// (BM_DelassusTrailingSolve, BM_DelassusBandFromFactor, BM_DelassusSweep).
/// From the second loop on the band is counted at half: a step that loops
/// again keeps it for the loops after (the matrix stays: curvature_loops).
bool fromBand(size_t d, const LoopState& s, const LoopSystem& sys) {
  const std::vector<ContactRow>& rows = sys.rows_of[d];
  const int c = static_cast<int>(rows.size());
  const int n = sys.factor[d]->size() / 6;
  int f = n;
  for (const ContactRow& row : rows)
    for (int part = 0; part < row.parts; ++part) f = std::min(f, std::max(0, row.offset[part] / 6));
  const Band wanted = s.curved[d] ? Band::kOfCurved : Band::kOfA;
  const double band = s.band[d] == wanted ? 0.0 : s.loop >= 2 ? 2.0 * n : 4.0 * n;
  return band + 24.0 * c < static_cast<double>(c) * (n - f);
}

/// Device d's operator H_d A^-1 H_d^T: from the block solve (*Wd, and Y)
/// or from the band (fromBand; kept in s->last_W[d] for the next loop;
/// returned). *kept counts the rows whose entries were kept.
const DelassusBuffer* deviceOperator(const ContactProblem& pb, size_t d, LoopState* s,
                                     LoopSystem* sys, MatX* Wd, int* kept) {
  auto& ws = *pb.workspaces;
  const std::vector<ContactRow>& device_rows = sys->rows_of[d];
  if (!fromBand(d, *s, *sys)) {
    delassusOperator(*sys->factor[d], device_rows, &sys->Y[d], Wd);
    return nullptr;
  }
  ensureBand(pb, d, s, sys);
  sys->Y[d].Y.resize(0, 0);
  // Rows unchanged since the last loop (same normal, and for a sample
  // at a node no tangent term) keep their entries among themselves.
  const std::vector<ContactRow>& before = s->last_rows[d];
  std::vector<char> changed(before.size(), 1);
  for (size_t r = 0; r < before.size() && r < device_rows.size(); ++r) {
    changed[r] = !sameRow(before[r], device_rows[r]);
    *kept += !changed[r];
  }
  updateChainDelassusOperator(ws[d].inverse, device_rows, changed, &s->last_W[d]);
  s->last_rows[d] = device_rows;
  return &s->last_W[d];
}

/// W's columns on demand rather than whole (contact/delassus_columns.h)
/// when that costs fewer flops: the status method starts from the
/// contacts with a force (the warm start) and reads about their columns
/// and the springs'; a column costs a pass along the chains (72 n) and its
/// dots with the rows (24 c) and, with r springs, 2 m r for their
/// elimination. Whole: the sweep (216 n + 6 c^2) and the elimination's
/// product (2 m^2 r). On arch_to_right_common_carotid's trunk stretch (220
/// rows, 40 forces, 25 springs) columns on demand take a third less time;
/// on a coil in a dome (15-300 rows, a long chain, no spring) the whole W
/// is cheaper.
bool columnsOnDemandPay(const ContactProblem& pb, const ContactOptions& o, const LoopState& s,
                        const LoopSystem& sys) {
  if (!o.columns_on_demand || pb.effects.friction || o.lcp.solver != LcpSolver::kStatusMethod)
    return false;
  double forces = 0.0, nodes = 0.0;
  for (int i = 0; i < sys.c; ++i) forces += (*s.contacts)[i].force > 0.0;
  for (const DeviceWorkspace& w : *pb.workspaces) nodes += w.factor.size() / 6;
  const double m = sys.m, r = static_cast<double>(sys.springs.size()), c = m + r;
  const double read = forces + r;
  const double on_demand = read * (72.0 * nodes + 24.0 * c + 2.0 * m * r);
  const double whole = 216.0 * nodes + 6.0 * c * c + 2.0 * m * m * r;
  return on_demand < whole;
}

}  // namespace

void formContactProblem(const ContactProblem& pb, const ContactOptions& o, LoopState* s,
                        LoopSystem* sys) {
  const size_t nd = pb.devices->size();
  const int m = sys->m;
  sys->q.resize(m);
  sys->mu.resize(pb.effects.friction ? sys->c : 0);
  if (pb.effects.friction) sys->tangents.resize(sys->c);
  // The rows' parts per device; their storage is kept from loop to loop
  // in the simulation's contact workspace.
  std::vector<std::vector<RowPart>> local;
  std::vector<std::vector<RowPart>>& parts = pb.kept ? pb.kept->kept().row_parts : local;
  parts.resize(std::max(parts.size(), nd));
  for (size_t d = 0; d < nd; ++d) {
    parts[d].clear();
    parts[d].reserve(2 * m + 2);
  }
  formRows(pb, o, *s, sys, &parts);
  addLumenSprings(pb, o, *s, sys, &parts);  // rows m, m + 1, ...: eliminated below
  const int rows = m + static_cast<int>(sys->springs.size());
  sys->of_device.assign(nd, {});
  sys->rows_of.assign(nd, {});
  sys->Y.assign(nd, TrailingSolve());
  std::vector<int> column_of_row;
  if (columnsOnDemandPay(pb, o, *s, *sys)) {
    sys->columns = std::make_unique<DelassusColumns>(rows);
    for (size_t d = 0; d < nd; ++d) {
      if (parts[d].empty()) continue;
      deviceRows(parts[d], (*pb.workspaces)[d].first_free_node, rows, &column_of_row,
                 &sys->of_device[d], &sys->rows_of[d]);
      if (!fromBand(d, *s, *sys)) {
        MatX Wd;
        delassusOperator(*sys->factor[d], sys->rows_of[d], &sys->Y[d], &Wd);
        sys->columns->addDense(std::move(Wd), &sys->of_device[d]);
        continue;
      }
      ensureBand(pb, d, s, sys);
      sys->columns->addChain(&(*pb.workspaces)[d].inverse, &sys->rows_of[d], &sys->of_device[d]);
    }
    eliminateLumenSprings(sys);
    return;
  }
  for (size_t d = 0; d < nd; ++d) {
    if (parts[d].empty()) continue;
    deviceRows(parts[d], (*pb.workspaces)[d].first_free_node, rows, &column_of_row,
               &sys->of_device[d], &sys->rows_of[d]);
    MatX Wd;
    const DelassusBuffer* kept = deviceOperator(pb, d, s, sys, &Wd, &sys->kept_rows);
    const MatXView Wdev = kept ? kept->view() : MatXView(Wd);  // this device's operator
    const auto& idx = sys->of_device[d];
    bool identity =
        !sys->W_device && sys->W_sum.size() == 0 && static_cast<int>(idx.size()) == rows;
    for (size_t a = 0; a < idx.size() && identity; ++a) identity = idx[a] == static_cast<int>(a);
    if (identity) {  // one device holds every row, in order: W is its operator
      if (kept)
        sys->W_device = kept;  // last_W[d], unchanged until the next loop
      else
        sys->W_sum.swap(Wd);
      continue;
    }
    if (sys->W_device) {  // a device before held every row, and this one shares some
      sys->W_sum = sys->W_device->view();
      sys->W_device = nullptr;
    }
    if (sys->W_sum.size() == 0) sys->W_sum = MatX::Zero(rows, rows);
    for (size_t b = 0; b < idx.size(); ++b)  // column by column (W is column-major)
      for (size_t a = 0; a < idx.size(); ++a) sys->W_sum(idx[a], idx[b]) += Wdev(a, b);
  }
  if (!sys->W_device && sys->W_sum.size() == 0) sys->W_sum = MatX::Zero(rows, rows);
  eliminateLumenSprings(sys);
}

bool predictFirstIterate(const ContactProblem& pb, LoopState* s) {
  if (!pb.previous || pb.previous->empty()) return false;
  const auto& devices = *pb.devices;
  const auto& start = *pb.start;
  const auto& ws = *pb.workspaces;
  const int nd = static_cast<int>(devices.size());
  std::vector<VecX> f(nd);  // H^T f over each device's free DOFs
  bool any = false;
  auto add = [&](int d, const SamplePoint& sp, const Vec3& force) {
    const int n = ws[d].factor.size();
    if (n == 0 || sp.element < 0 || sp.element + 1 >= static_cast<int>(start[d].position.size()))
      return;
    if (f[d].size() == 0) f[d] = VecX::Zero(n);
    const Row12 h = contactRow(devices[d], start[d], sp, force);
    const int offset = 6 * (sp.element - ws[d].first_free_node);
    for (int k = 0; k < 12; ++k)
      if (offset + k >= 0 && offset + k < n) f[d](offset + k) += h(k);
    any = true;
  };
  for (const Contact& ct : *pb.previous) {
    if (!(ct.force > 0.0) || ct.device >= nd || ct.other_device >= nd) continue;
    if (ct.other_device < 0 && ct.sample >= static_cast<int>((*pb.samples)[ct.device].size()))
      continue;
    const Vec3 force = ct.force * ct.normal + ct.friction;
    add(ct.device, contactPointOf(ct, *pb.samples), force);
    if (ct.other_device >= 0) add(ct.other_device, ct.other, -force);
  }
  if (!any) return false;
  for (int d = 0; d < nd; ++d) {
    if (f[d].size() == 0) continue;
    ws[d].factor.solveInPlace(&f[d]);
    s->dq[d].tail(f[d].size()) += f[d];
  }
  placeIterate(pb, s);
  return true;
}

void placeAtFreeMotion(const ContactProblem& pb, LoopState* s) {
  s->dq = s->dq_free;
  placeIterate(pb, s);
}

void restartAtFreeMotion(const ContactProblem& pb, LoopState* s) {
  placeAtFreeMotion(pb, s);
  s->contacts->clear();
  s->formed.clear();
  for (auto& of : s->contact_of) std::fill(of.begin(), of.end(), -1);
  s->pair_contact.clear();
  for (auto& of : s->lumen_of) std::fill(of.begin(), of.end(), -1);
}

void correctMotion(const ContactProblem& pb, const LoopSystem& sys, const VecX& lambda,
                   LoopState* s) {
  auto& ws = *pb.workspaces;
  const size_t nd = ws.size();
  const int dim = pb.effects.friction ? 3 : 1;
  VecX forces = lambda;  // with the lumen's curvature springs' after the contacts'
  if (!sys.springs.empty()) {
    forces.resize(sys.m + static_cast<int>(sys.springs.size()));
    forces.head(sys.m) = lambda;
    forces.tail(sys.springs.size()) = lumenSpringForces(sys, lambda);
  }
  for (size_t d = 0; d < nd; ++d) {
    s->dq[d] = sys.dq_step[d];
    const auto& idx = sys.of_device[d];
    if (idx.empty()) continue;
    VecX l(idx.size());
    for (size_t j = 0; j < idx.size(); ++j) l(j) = forces(idx[j]);
    const int n = sys.factor[d]->size();
    if (sys.Y[d].Y.cols() > 0) {  // W came from the block solve
      addSolveTimes(*sys.factor[d], sys.Y[d], l, s->dq[d].tail(n));
    } else {
      VecX correction = contactForce(n, sys.rows_of[d], l);
      ws[d].inverse.solveInPlace(&correction);  // the LDL^T of the band's matrix
      s->dq[d].tail(n) += correction;
    }
  }
  placeIterate(pb, s);
  for (int i = 0; i < sys.c; ++i) {
    Contact& ct = (*s->contacts)[i];
    ct.force = lambda(dim * i);
    if (pb.effects.friction)
      ct.friction = lambda(3 * i + 1) * sys.tangents[i][0] + lambda(3 * i + 2) * sys.tangents[i][1];
  }
}

}  // namespace evsim::activation
