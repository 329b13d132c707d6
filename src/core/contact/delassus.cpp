#include "endovascular_sim/contact/delassus.h"

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

}  // namespace evsim
