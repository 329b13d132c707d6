#include "endovascular_sim/contact/delassus.h"

#include <algorithm>

namespace evsim {

void delassusOperator(SparseCholesky& cholesky, const std::vector<ContactRow>& rows, MatX* Y,
                      MatX* W) {
  const int n = cholesky.size();
  const int c = static_cast<int>(rows.size());
  MatX Ht = MatX::Zero(n, c);
  for (int j = 0; j < c; ++j)
    for (int part = 0; part < rows[j].parts; ++part)
      for (int k = 0; k < 12; ++k) {
        const int dof = rows[j].offset[part] + k;
        if (dof >= 0 && dof < n) Ht(dof, j) += rows[j].h[part](k);
      }
  cholesky.solve(Ht, Y);
  W->resize(c, c);
  for (int i = 0; i < c; ++i)
    for (int j = 0; j <= i; ++j) {
      double w = 0.0;
      for (int part = 0; part < rows[i].parts; ++part)
        for (int k = 0; k < 12; ++k) {
          const int dof = rows[i].offset[part] + k;
          if (dof >= 0 && dof < n) w += rows[i].h[part](k) * (*Y)(dof, j);
        }
      (*W)(i, j) = (*W)(j, i) = w;
    }
}

namespace {

/// One part of a row on the nodes (node, node + 1) of the free chain.
struct Part {
  int row;
  int node;
  Vec6 lo, hi;  // coefficients on the two nodes
};

/// The rows' parts sorted by node; a part whose first node is held keeps
/// its second (as `lo` on free node 0), a part with both held is dropped.
std::vector<Part> sortedParts(const std::vector<ContactRow>& rows, int blocks) {
  std::vector<Part> parts;
  for (size_t r = 0; r < rows.size(); ++r)
    for (int k = 0; k < rows[r].parts; ++k) {
      const int node = rows[r].offset[k] / 6;
      const Row12& h = rows[r].h[k];
      if (node < -1 || node >= blocks) continue;
      Part p{static_cast<int>(r), node, h.head<6>().transpose(), h.tail<6>().transpose()};
      if (node == -1) p = {p.row, 0, p.hi, Vec6::Zero()};
      if (p.node + 1 >= blocks) p.hi.setZero();
      parts.push_back(p);
    }
  std::stable_sort(parts.begin(), parts.end(),
                   [](const Part& a, const Part& b) { return a.node < b.node; });
  return parts;
}

}  // namespace

void chainDelassusOperator(const ChainInverse& inverse, const std::vector<ContactRow>& rows,
                           MatX* W) {
  const int c = static_cast<int>(rows.size());
  *W = MatX::Zero(c, c);
  const int blocks = inverse.numBlocks();
  std::vector<Part> parts = sortedParts(rows, blocks);
  if (parts.empty()) return;
  std::reverse(parts.begin(), parts.end());  // from the top of the chain down
  const int count = static_cast<int>(parts.size());
  // One sweep down the chain carries the columns S g_b of every part started
  // so far: column b of `here` holds S g_b at node i, of `above` at i + 1.
  // A part's column starts at its own node from the band of S; below its
  // nodes it is carried by S_ij g = -L_{i+1}^T S_{i+1,j} g, all columns in one
  // 6 x 6 by 6 x k product. At node i each part a on it is dotted with every
  // column: W_ab for the parts b above it (both halves of W) and for the
  // parts on the same node from a on (each pair once).
  using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;
  Mat6X here(6, count), above(6, count);
  Eigen::RowVectorXd dots(count);
  int active = 0;  // columns started
  for (int next = 0; next < count;) {
    const int i = parts[next].node;
    if (active > 0) {  // carry the started columns down to node i
      for (int node = parts[next - 1].node - 1; node >= i; --node) {
        here.swap(above);  // (O(1): the buffers trade places)
        here.leftCols(active).noalias() = -inverse.lowerTransposed(node) * above.leftCols(active);
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
    }
    for (int a = next; a < active; ++a) {
      const Part& pa = parts[a];
      dots.head(active).noalias() =
          pa.lo.transpose() * here.leftCols(active) + pa.hi.transpose() * above.leftCols(active);
      for (int b = 0; b < started; ++b) {
        (*W)(pa.row, parts[b].row) += dots(b);
        (*W)(parts[b].row, pa.row) += dots(b);
      }
      (*W)(pa.row, pa.row) += dots(a);
      for (int b = a + 1; b < active; ++b) {
        (*W)(pa.row, parts[b].row) += dots(b);
        (*W)(parts[b].row, pa.row) += dots(b);
      }
    }
    next = active;
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
