// The Delassus operator W = H A^-1 H^T of one device, without forming A^-1.
// Declared and documented in endovascular_sim/contact/delassus.h.
#include "endovascular_sim/core/thread_cache.h"
#include "endovascular_sim/contact/delassus.h"

#include <algorithm>

namespace evsim {

namespace {

/// The first free DOF a row reaches (n: none).
int firstDof(int n, const std::vector<ContactRow>& rows) {
  int first = n;
  for (const ContactRow& row : rows)
    for (int part = 0; part < row.parts; ++part)
      for (int k = 0; k < 12; ++k) {
        const int dof = row.offset[part] + k;
        if (dof >= 0 && dof < n) first = std::min(first, dof);
      }
  return first;
}

/// H^T's rows [from, n) into *Ht ((n - from) x c).
void fillTransposedRows(int n, const std::vector<ContactRow>& rows, MatX* Ht, int from = 0) {
  const int c = static_cast<int>(rows.size());
  Ht->setZero(n - from, c);
  for (int j = 0; j < c; ++j)
    for (int part = 0; part < rows[j].parts; ++part)
      for (int k = 0; k < 12; ++k) {
        const int dof = rows[j].offset[part] + k;
        if (dof >= from && dof < n) (*Ht)(dof - from, j) += rows[j].h[part](k);
      }
}

}  // namespace

MatX transposedRows(int n, const std::vector<ContactRow>& rows) {
  MatX Ht;
  fillTransposedRows(n, rows, &Ht);
  return Ht;
}

void delassusOperator(const ChainFactor& factor, const std::vector<ContactRow>& rows, MatX* Y,
                      MatX* W) {
  fillTransposedRows(factor.size(), rows, Y);
  factor.solveInPlace(Y, firstDof(factor.size(), rows) / 6);
  rowsTimes(rows, *Y, W);
}

void rowsTimes(const std::vector<ContactRow>& rows, const MatX& Y, MatX* W, int first_dof) {
  const int c = static_cast<int>(rows.size());
  const int n = first_dof + static_cast<int>(Y.rows());
  W->resize(c, c);
  for (int i = 0; i < c; ++i)
    for (int j = 0; j <= i; ++j) {
      double w = 0.0;
      for (int part = 0; part < rows[i].parts; ++part)
        for (int k = 0; k < 12; ++k) {
          const int dof = rows[i].offset[part] + k;
          if (dof >= first_dof && dof < n) w += rows[i].h[part](k) * Y(dof - first_dof, j);
        }
      (*W)(i, j) = (*W)(j, i) = w;
    }
}

void delassusOperator(const ChainFactor& factor, const std::vector<ContactRow>& rows,
                      TrailingSolve* Y, MatX* W) {
  const int n = factor.size();
  Y->first_block = firstDof(n, rows) / 6;
  const int from = 6 * Y->first_block;
  fillTransposedRows(n, rows, &Y->Y, from);
  factor.solveTrailingInPlace(&Y->Y, Y->first_block);
  rowsTimes(rows, Y->Y, W, from);
}

void addSolveTimes(const ChainFactor& factor, const TrailingSolve& Y, const VecX& l,
                   Eigen::Ref<VecX> dq) {
  const int from = 6 * Y.first_block;
  dq.tail(dq.size() - from).noalias() += Y.Y * l;
  if (from == 0 || Y.Y.rows() == 0) return;
  // Above the rows A^-1 H^T l solves L^T x = 0: x_i = -L_{i+1}^T x_{i+1}.
  Vec6 x = Y.Y.topRows<6>() * l;
  for (int i = Y.first_block - 1; i >= 0; --i) {
    x = factor.transfer(i) * x;
    dq.segment<6>(6 * i) += x;
  }
}

namespace {

/// The update computes only the fresh rows' columns when there are at most
/// (c + kFreshColumnsBase) / kFreshColumnsPerRow of c rows (else one sweep
/// with every column). BM_DelassusUpdate on the packed coil's 625-element
/// chain: the two paths cost the same at about 7, 12-16 and 20-24 fresh rows
/// of 100, 300 and 500.
constexpr int kFreshColumnsBase = 100;
constexpr int kFreshColumnsPerRow = 25;

using Part = ChainPart;

using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using MatX6 = Eigen::Matrix<double, Eigen::Dynamic, 6>;

/// The buffers of one update of W, kept per thread from call to call: they
/// only grow, so that a step allocates nothing here once it has met its
/// largest problem (the loop updates W a few times a step).
struct UpdateScratch {
  std::vector<Part> unsorted, parts;
  std::vector<int> parts_before;  // sortParts' counts per node
  std::vector<char> is_fresh_row;
  std::vector<int> fresh_list, fresh_parts, fresh_columns;
  std::vector<int> row_of, partner, first_part_of_row;
  Mat6X here, above, r;  // carried columns (at least as many as asked for)
  MatX6 settled;
  VecX dots;
};

UpdateScratch& updateScratch() {
  return threadCache<UpdateScratch>();
}

/// At least `cols` columns (`rows` rows) in a buffer that only grows.
void reserveCols(Mat6X* m, int cols) {
  if (m->cols() < cols) m->resize(6, cols);
}
void reserveRows(MatX6* m, int rows) {
  if (m->rows() < rows) m->resize(rows, 6);
}
void reserveSize(VecX* v, int size) {
  if (v->size() < size) v->resize(size);
}

/// The rows' parts sorted by node, in row order within a node (a counting
/// sort: O(parts + blocks)), into *parts (*unsorted and *before: its
/// buffers); a part whose first node is held keeps its second (as `lo` on
/// free node 0), a part with both held is dropped.
void sortParts(const std::vector<ContactRow>& rows, int blocks, std::vector<Part>* unsorted,
               std::vector<int>* before, std::vector<Part>* parts) {
  unsorted->clear();
  std::vector<int>& start = *before;  // parts before each node
  start.assign(blocks + 1, 0);
  for (size_t r = 0; r < rows.size(); ++r)
    for (int k = 0; k < rows[r].parts; ++k) {
      const int node = rows[r].offset[k] / 6;
      const Row12& h = rows[r].h[k];
      if (node < -1 || node >= blocks) continue;
      Part p{static_cast<int>(r), node, h.head<6>().transpose(), h.tail<6>().transpose()};
      if (node == -1) p = {p.row, 0, p.hi, Vec6::Zero()};
      if (p.node + 1 >= blocks) p.hi.setZero();
      unsorted->push_back(p);
      ++start[p.node + 1];
    }
  for (int i = 0; i < blocks; ++i) start[i + 1] += start[i];
  parts->resize(unsorted->size());
  for (const Part& p : *unsorted) (*parts)[start[p.node]++] = p;
}

std::vector<Part> sortedParts(const std::vector<ContactRow>& rows, int blocks) {
  std::vector<Part> unsorted, parts;
  std::vector<int> before;
  sortParts(rows, blocks, &unsorted, &before, &parts);
  return parts;
}

/// W + W^T off the diagonal, the diagonal kept: each pair was added to one
/// half only. In 32 x 32 tiles (the transpose's reads stay in cache);
/// exactly symmetric.
void symmetrizeHalves(Eigen::Ref<MatX> W) {
  constexpr int kTile = 32;
  const int c = static_cast<int>(W.rows());
  for (int j0 = 0; j0 < c; j0 += kTile)
    for (int i0 = j0; i0 < c; i0 += kTile) {
      const int jn = std::min(kTile, c - j0), in = std::min(kTile, c - i0);
      for (int j = j0; j < j0 + jn; ++j)
        for (int i = std::max(i0, j + 1); i < i0 + in; ++i) {
          const double sum = W(i, j) + W(j, i);
          W(i, j) = sum;
          W(j, i) = sum;
        }
    }
}

/// A part's own column S g at its first node i: S_ii lo + S_{i,i+1} hi.
Vec6 columnHere(const ChainInverse& inverse, const Part& p) {
  Vec6 here = inverse.diagonal(p.node) * p.lo;
  if (p.node + 1 < inverse.numBlocks())
    here.noalias() += inverse.subdiagonal(p.node).transpose() * p.hi;
  return here;
}

/// The same column at node i + 1: S_{i+1,i} lo + S_{i+1,i+1} hi.
Vec6 columnAbove(const ChainInverse& inverse, const Part& p) {
  if (p.node + 1 >= inverse.numBlocks()) return Vec6::Zero();
  return inverse.subdiagonal(p.node) * p.lo + inverse.diagonal(p.node + 1) * p.hi;
}

/// Adds to W(:, b.row), for every fresh part b, g_a^T S g_b of every part a
/// (parts sorted by node, ascending). Two sweeps, each carrying only the
/// fresh parts, 36 flops per part and node:
///  - down the chain, b's column S g_b (from its own nodes down:
///    S_kj g = Phi(k <- j) S_jj g, Phi(k <- k+1) = -L_{k+1}^T), dotted with
///    the parts a at or below b's node: lo_a . col(i) + hi_a . col(i + 1);
///  - up the chain, the row r_b(i) = Phi(j <- i)^T lo_b + Phi(j+1 <- i)^T hi_b
///    (r_b(i + 1) = -L_{i+1} r_b(i)), dotted with the own column of each
///    part a above b's node: g_b^T S g_a = r_b(i) . (S g_a)(i).
/// Every pair (a, b fresh) once; the caller mirrors the fresh columns.
void addFreshColumns(const ChainInverse& inverse, const std::vector<Part>& parts,
                     const std::vector<int>& fresh_parts, Eigen::Ref<MatX> W) {
  const int f = static_cast<int>(fresh_parts.size());
  const int count = static_cast<int>(parts.size());
  if (f == 0) return;
  UpdateScratch& scratch = updateScratch();
  Mat6X& here = scratch.here;
  Mat6X& above = scratch.above;
  VecX& dots = scratch.dots;
  reserveCols(&here, f);
  reserveCols(&above, f);
  reserveSize(&dots, f);
  // Down: fresh columns started at their nodes, highest first.
  int started = 0;  // fresh_parts[f - started, f) are started
  int node = parts[fresh_parts[f - 1]].node;
  for (int a = count - 1; a >= 0; --a) {
    const Part& pa = parts[a];
    if (pa.node > parts[fresh_parts[f - 1]].node) continue;
    for (; node > pa.node; --node) {  // carry the started columns to node - 1
      const int first = f - started;
      here.swap(above);  // (O(1): the buffers trade places)
      here.middleCols(first, started).noalias() =
          inverse.transfer(node - 1) * above.middleCols(first, started);
    }
    for (; started < f && parts[fresh_parts[f - 1 - started]].node == pa.node; ++started) {
      const int col = f - 1 - started;
      here.col(col) = columnHere(inverse, parts[fresh_parts[col]]);
      above.col(col) = columnAbove(inverse, parts[fresh_parts[col]]);
    }
    const int first = f - started;
    dots.head(started).noalias() = here.middleCols(first, started).transpose() * pa.lo +
                                   above.middleCols(first, started).transpose() * pa.hi;
    for (int k = 0; k < started; ++k) W.col(parts[fresh_parts[first + k]].row)(pa.row) += dots(k);
  }
  // Up: rows of the fresh parts strictly below each part a.
  Mat6X& r = scratch.r;
  reserveCols(&r, f);
  started = 0;  // fresh_parts[0, started) are started, r at node `node`
  node = parts[fresh_parts[0]].node;
  for (int a = 0; a < count; ++a) {
    const Part& pa = parts[a];
    if (pa.node <= parts[fresh_parts[0]].node) continue;
    for (; node < pa.node; ++node) {  // r_b(node + 1) from r_b(node); start parts at `node`
      r.leftCols(started) = inverse.transfer(node).transpose() * r.leftCols(started);
      for (; started < f && parts[fresh_parts[started]].node == node; ++started) {
        const Part& pb = parts[fresh_parts[started]];
        r.col(started) = pb.hi + inverse.transfer(node).transpose() * pb.lo;
      }
    }
    dots.head(started).noalias() = r.leftCols(started).transpose() * columnHere(inverse, pa);
    for (int k = 0; k < started; ++k) W.col(parts[fresh_parts[k]].row)(pa.row) += dots(k);
  }
}

/// Adds to one half of W every pair of parts with a fresh row (is_fresh_row)
/// in one sweep down the chain (parts sorted by node, descending: from the
/// top of the chain down). One function of about 100 lines: the sweep's
/// state (carried columns, transfer, checkpoint) is what every step of it
/// updates; split, it would pass through a dozen arguments.
void sweepColumns(const ChainInverse& inverse, const std::vector<Part>& parts,
                  const std::vector<char>& is_fresh_row, Eigen::Ref<MatX> W) {
  const int blocks = inverse.numBlocks();
  const int count = static_cast<int>(parts.size());
  // One sweep down the chain carries the columns S g_b of every part started
  // so far. A part's column starts at its own node from the band of S; below
  // its nodes it follows S_ij g = -L_{i+1}^T S_{i+1,j} g. Carrying every
  // column node by node costs 36 k per node for k columns; instead the
  // columns are settled at a checkpoint node k and only the 6 x 6 transfer
  // T = Phi(i <- k) = (-L_{i+1}^T) ... (-L_k^T) is carried (216 per node):
  // at node i the columns are T S_k. Columns started since the checkpoint
  // (young) are carried explicitly; once there are kYoungColumns of them, or
  // the checkpoint lies kSpanNodes above, all are settled at the current node
  // (36 k). At node i each part a is dotted with the columns: settled ones
  // through u_a = T_i^T lo_a + T_{i+1}^T hi_a, young ones directly; W_ab for
  // the parts b above it and for the parts on the same node from a on (each
  // pair once). A pair of kept rows is not dotted: its entry is copied.
  constexpr int kYoungColumns = 16;
  constexpr int kSpanNodes = 32;
  UpdateScratch& scratch = updateScratch();
  Mat6X& here = scratch.here;
  Mat6X& above = scratch.above;
  MatX6& settled = scratch.settled;  // settled columns, transposed: dots are 6 contiguous axpys
  VecX& dots = scratch.dots;
  reserveCols(&here, count);
  reserveCols(&above, count);
  reserveRows(&settled, count);
  reserveSize(&dots, count);
  std::vector<int>& fresh_columns =
      scratch.fresh_columns;  // started columns of fresh rows, ascending
  fresh_columns.clear();
  Mat6 T = Mat6::Identity(), T_above = Mat6::Identity();
  int settled_count = 0;  // columns [0, settled_count) are settled at node `checkpoint`
  int active = 0;         // columns started; [settled_count, active) are young
  int checkpoint = blocks;
  // One half of W, in column pa.row (contiguous); W + W^T below. The two
  // parts of one self-contact row meet on its diagonal twice.
  auto add = [&](const Part& pa, const Part& pb, double w) {
    W.col(pa.row)(pb.row) += pb.row == pa.row && &pa != &pb ? 2.0 * w : w;
  };
  // The same for runs of parts b, from their rows (contiguous) and each
  // part's partner (the other part of its row, or -1): the partner's dot
  // doubled beforehand, the run adds without a test.
  std::vector<int>& row_of = scratch.row_of;
  std::vector<int>& partner = scratch.partner;
  std::vector<int>& first_part_of_row = scratch.first_part_of_row;
  row_of.resize(count);
  partner.assign(count, -1);
  first_part_of_row.assign(W.rows(), -1);
  for (int k = 0; k < count; ++k) {
    row_of[k] = parts[k].row;
    int& first = first_part_of_row[parts[k].row];
    if (first >= 0) {
      partner[k] = first;
      partner[first] = k;
    } else {
      first = k;
    }
  }
  auto addRun = [&](int a, int begin, int end) {
    const int p = partner[a];
    if (p >= begin && p < end && p != a) dots(p) *= 2.0;
    double* column = W.col(row_of[a]).data();
    for (int b = begin; b < end; ++b) column[row_of[b]] += dots(b);
  };
  for (int next = 0; next < count;) {
    const int i = parts[next].node;
    if (active > 0) {  // carry the transfer and the young columns down to node i
      const int young = active - settled_count;
      for (int node = parts[next - 1].node - 1; node >= i; --node) {
        const Mat6& transfer = inverse.transfer(node);
        if (settled_count > 0) {
          T_above = T;
          T.noalias() = transfer * T_above;
        }
        here.swap(above);  // (O(1): the buffers trade places)
        here.middleCols(settled_count, young).noalias() =
            transfer * above.middleCols(settled_count, young);
      }
    }
    const int started = active;  // columns of the parts above node i
    for (; active < count && parts[active].node == i; ++active) {
      const Part& b = parts[active];
      here.col(active) = inverse.diagonal(i) * b.lo;
      above.col(active).setZero();
      if (i + 1 < blocks) {
        here.col(active).noalias() += inverse.subdiagonal(i).transpose() * b.hi;
        above.col(active).noalias() =
            inverse.subdiagonal(i) * b.lo + inverse.diagonal(i + 1) * b.hi;
      }
      if (is_fresh_row[b.row]) fresh_columns.push_back(active);
    }
    const int young = active - settled_count;
    for (int a = next; a < active; ++a) {
      const Part& pa = parts[a];
      Vec6 u = Vec6::Zero();
      if (settled_count > 0) u = T.transpose() * pa.lo + T_above.transpose() * pa.hi;
      if (is_fresh_row[pa.row]) {  // with every column
        if (settled_count > 0)
          dots.head(settled_count).noalias() = settled.topRows(settled_count) * u;
        dots.segment(settled_count, young).noalias() =
            here.middleCols(settled_count, young).transpose() * pa.lo +
            above.middleCols(settled_count, young).transpose() * pa.hi;
        addRun(a, 0, started);
        addRun(a, a, active);
        continue;
      }
      for (int b : fresh_columns) {           // a kept row: with the fresh columns only
        if (b >= started && b < a) continue;  // same node, counted from b
        const double w = b < settled_count ? settled.row(b).dot(u.transpose())
                                           : pa.lo.dot(here.col(b)) + pa.hi.dot(above.col(b));
        add(pa, parts[b], w);
      }
    }
    next = active;
    if (young >= kYoungColumns || (settled_count > 0 && checkpoint - i >= kSpanNodes)) {
      // Settle every column at node i.
      for (int k = 0; k < settled_count; ++k) {  // each settled column moved by T
        const Eigen::Matrix<double, 1, 6> moved = settled.row(k) * T.transpose();
        settled.row(k) = moved;
      }
      settled.middleRows(settled_count, young) = here.middleCols(settled_count, young).transpose();
      settled_count = active;
      T.setIdentity();
      checkpoint = i;
    }
  }
}

/// W (c x c) in the buffer: the previous operator among its first
/// kept_rows rows where neither row is fresh (final there), 0 elsewhere;
/// beyond the capacity the kept block is copied once into a buffer half as
/// large again.
Eigen::Block<MatX> keepUnchangedEntries(int c, int kept_rows, const std::vector<int>& fresh_list,
                                        DelassusBuffer* buffer) {
  if (c > buffer->storage.rows()) {
    const int capacity = std::max(c, static_cast<int>(3 * buffer->storage.rows() / 2));
    MatX grown(capacity, capacity);
    grown.topLeftCorner(kept_rows, kept_rows) = buffer->storage.topLeftCorner(kept_rows, kept_rows);
    buffer->storage.swap(grown);
  }
  buffer->size = c;
  Eigen::Block<MatX> W = buffer->matrix();
  if (kept_rows < c) {  // the added rows and columns start at zero
    W.bottomRows(c - kept_rows).setZero();
    W.topRightCorner(kept_rows, c - kept_rows).setZero();
  }
  for (int f : fresh_list) {
    if (f >= kept_rows) break;
    W.row(f).head(kept_rows).setZero();
    W.col(f).head(kept_rows).setZero();
  }
  return W;
}

}  // namespace

void chainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                           MatX* W) {
  W->resize(0, 0);
  updateChainDelassusOperator(inverse, rows, std::vector<char>(), W);
}

void updateChainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                                 const std::vector<char>& fresh_rows, MatX* W,
                                 DelassusUpdate path) {
  DelassusBuffer buffer;
  if (W->rows() == W->cols()) {
    buffer.storage.swap(*W);
    buffer.size = static_cast<int>(buffer.storage.rows());
  }
  updateChainDelassusOperator(inverse, rows, fresh_rows, &buffer, path);
  if (buffer.storage.rows() == buffer.size)
    W->swap(buffer.storage);
  else
    *W = buffer.view();
}

void updateChainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                                 const std::vector<char>& fresh_rows, DelassusBuffer* buffer,
                                 DelassusUpdate path) {
  const int c = static_cast<int>(rows.size());
  if (buffer->size > c) buffer->size = 0;  // nothing to keep
  const int kept_rows = buffer->size;
  UpdateScratch& scratch = updateScratch();
  std::vector<char>& is_fresh_row = scratch.is_fresh_row;
  std::vector<int>& fresh_list = scratch.fresh_list;
  is_fresh_row.assign(c, 0);
  fresh_list.clear();
  for (int i = 0; i < c; ++i)
    if (i >= kept_rows || (i < static_cast<int>(fresh_rows.size()) && fresh_rows[i])) {
      is_fresh_row[i] = 1;
      fresh_list.push_back(i);
    }
  Eigen::Block<MatX> W = keepUnchangedEntries(c, kept_rows, fresh_list, buffer);
  const int blocks = inverse.numBlocks();
  std::vector<Part>& parts = scratch.parts;
  sortParts(rows, blocks, &scratch.unsorted, &scratch.parts_before, &parts);
  const bool few =
      kFreshColumnsPerRow * static_cast<int>(fresh_list.size()) <= c + kFreshColumnsBase;
  if (kept_rows > 0 && path != DelassusUpdate::kSweep &&
      (path == DelassusUpdate::kFreshColumns || few)) {
    // Few fresh rows: their columns alone, then mirrored into their rows
    // (a pair of fresh rows from the higher one's column).
    std::vector<int>& fresh_parts = scratch.fresh_parts;
    fresh_parts.clear();
    for (size_t k = 0; k < parts.size(); ++k)
      if (is_fresh_row[parts[k].row]) fresh_parts.push_back(static_cast<int>(k));
    addFreshColumns(inverse, parts, fresh_parts, W);
    for (int f : fresh_list)
      for (int i = 0; i < c; ++i)
        if (!is_fresh_row[i] || i < f) W(f, i) = W(i, f);
    return;
  }
  std::reverse(parts.begin(), parts.end());  // from the top of the chain down
  sweepColumns(inverse, parts, is_fresh_row, W);
  if (kept_rows == 0) {  // every pair in one half
    symmetrizeHalves(W);
    return;
  }
  // The pairs with a fresh row are in one half: add the halves there only
  // (a fresh pair once, from its lower index; the diagonal is whole).
  for (int f : fresh_list)
    for (int i = 0; i < c; ++i) {
      if (is_fresh_row[i] && i <= f) continue;
      const double sum = W(i, f) + W(f, i);
      W(i, f) = sum;
      W(f, i) = sum;
    }
}

ChainColumns::ChainColumns(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                           std::vector<int> to)
    : inverse_(&inverse),
      parts_(sortedParts(rows, inverse.numBlocks())),
      to_(std::move(to)),
      parts_of_row_(rows.size()) {
  here_.resize(parts_.size());
  for (size_t k = 0; k < parts_.size(); ++k) {
    here_[k] = columnHere(inverse, parts_[k]);
    parts_of_row_[parts_[k].row].push_back(static_cast<int>(k));
  }
}

template <typename Sink>
void ChainColumns::forColumn(int j, Sink&& sink) const {
  const ChainInverse& inverse = *inverse_;
  const int count = static_cast<int>(parts_.size());
  for (int k : parts_of_row_[j]) {
    const Part& b = parts_[k];
    // Down the chain: S g_b at each node (col(i - 1) = transfer(i - 1)
    // col(i) below b's first node), dotted with every part at or below it.
    int last = k;  // and the parts on b's node after it
    while (last + 1 < count && parts_[last + 1].node == b.node) ++last;
    Vec6 here = here_[k], above = columnAbove(inverse, b);
    int node = b.node;
    for (int a = last; a >= 0; --a) {
      const Part& pa = parts_[a];
      for (; node > pa.node; --node) {
        above = here;
        here.noalias() = inverse.transfer(node - 1) * above;
      }
      sink(pa.row, pa.lo.dot(here) + pa.hi.dot(above));
    }
    // Up the chain: the row r(i + 1) = transfer(i)^T r(i) from
    // r(node + 1) = hi + transfer(node)^T lo, dotted with the own column
    // of every part above b's node.
    if (last + 1 >= count) continue;
    Vec6 r = b.hi + inverse.transfer(b.node).transpose() * b.lo;
    node = b.node + 1;
    for (int a = last + 1; a < count; ++a) {
      const Part& pa = parts_[a];
      for (; node < pa.node; ++node) r = (inverse.transfer(node).transpose() * r).eval();
      sink(pa.row, r.dot(here_[a]));
    }
  }
}

void ChainColumns::addColumn(int j, double* out) const {
  forColumn(j, [&](int row, double w) { out[to_[row]] += w; });
}

void ChainColumns::addDiagonal(double* out) const {
  for (size_t k = 0; k < parts_.size(); ++k) {
    const Part& p = parts_[k];
    const std::vector<int>& own = parts_of_row_[p.row];
    if (own.size() == 1) {
      out[to_[p.row]] += p.lo.dot(here_[k]) + p.hi.dot(columnAbove(*inverse_, p));
    } else if (static_cast<int>(k) == own.front()) {
      // A self contact's row couples its two elements: from its column.
      forColumn(p.row, [&](int row, double w) {
        if (row == p.row) out[to_[row]] += w;
      });
    }
  }
}

VecX contactForce(int n, const std::vector<ContactRow>& rows, const VecX& lambda) {
  VecX f = VecX::Zero(n);
  for (size_t j = 0; j < rows.size(); ++j)
    for (int part = 0; part < rows[j].parts; ++part)
      for (int k = 0; k < 12; ++k) {
        const int dof = rows[j].offset[part] + k;
        if (dof >= 0 && dof < n) f(dof) += lambda(j) * rows[j].h[part](k);
      }
  return f;
}

}  // namespace evsim
