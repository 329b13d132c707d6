// The Delassus operator W = H A^-1 H^T of one device, without forming A^-1.
//
// Each contact row of H has 12 non-zeros (two nodes). One CHOLMOD solve with
// a block of c right-hand sides gives Y = A^-1 H^T (O(c n) for a chain:
// banded triangular solves), then W_ij = h_i . Y_j over the 12 non-zeros of
// h_i (O(c^2)). The naive alternative — c separate solves and a dense
// product H Y, O(c n) + O(c^2 n) — is measured against it in the benchmarks.
#pragma once

#include <vector>

#include "endovascular_sim/contact/contact_point.h"
#include "endovascular_sim/mechanics/sparse_cholesky.h"

namespace evsim {

/// A row of H restricted to one device: one or two parts (a self contact
/// touches two elements of the device), each the offset of its first node
/// among the free DOFs (6 * (node - first_free), negative for a held node)
/// and its 12 coefficients.
struct ContactRow {
  int parts{1};
  int offset[2]{0, 0};
  Row12 h[2]{Row12::Zero(), Row12::Zero()};
};

/// Y = A^-1 H^T (free DOFs x c) and W = H Y (c x c).
void delassusOperator(SparseCholesky& cholesky, const std::vector<ContactRow>& rows, MatX* Y,
                      MatX* W);

}  // namespace evsim
