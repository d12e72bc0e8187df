// Solving with a dense LDL^T kept in one column-major n x n array: L (unit, below the diagonal)
// and D (on it). Shared by the exact solver's small loops and the tree factorization's blocks,
// which each factor in their own way (their shifts differ) and solve alike.
#pragma once

namespace linx::solver {

/// x = (L D L^T)^-1 x for the factors in a (n x n, column-major).
inline void solveLdlt(const double* a, int n, double* x) {
  for (int j = 0; j < n; ++j) {
    double v = x[j];
    for (int k = 0; k < j; ++k) v -= a[j + k * n] * x[k];
    x[j] = v;
  }
  for (int j = 0; j < n; ++j) x[j] /= a[j + j * n];
  for (int j = n - 1; j >= 0; --j) {
    double v = x[j];
    for (int i = j + 1; i < n; ++i) v -= a[i + j * n] * x[i];
    x[j] = v;
  }
}

}  // namespace linx::solver
