// Solving with a dense LDL^T kept in one column-major n x n array: L (unit, below the diagonal)
// and D (on it), and which of its pivots are redundant rows. Shared by the exact solver's small
// loops and the tree factorization's blocks, which each factor in their own way (their shifts
// differ) and solve alike, and by the small systems of equalities (solver/dense_equalities),
// factored as they are.
#pragma once

namespace linx::solver {

/// Whether a pivot d of an L D L^T whose row has `diagonal` (J M^-1 J^T + cfm) is nothing but
/// regularization, the row's cfm and the factorization's shift: a redundant row (every exact
/// back-end and the small dense solves count them alike).
inline bool isRedundantPivot(double d, double diagonal, double cfm, double shift) {
  return d <= 1e-8 * (diagonal - cfm) + 10.0 * (cfm + shift);
}

/// Column j of an L D L^T factorization in place, its pivot D(j) already on the diagonal:
/// L(i, j) for every i > j, from the columns before it. Every factorization here shares it.
inline void eliminateBelow(double* a, int n, int j) {
  const double d = a[j + j * n];
  for (int i = j + 1; i < n; ++i) {
    double v = a[i + j * n];
    for (int k = 0; k < j; ++k) v -= a[i + k * n] * a[j + k * n] * a[k + k * n];
    a[i + j * n] = v / d;
  }
}

/// L D L^T of the symmetric n x n column-major matrix a in place, without pivoting (its lower
/// triangle read; L, unit, written below the diagonal and D on it). Returns false, at the first
/// pivot that is not positive, when a is not positive definite.
inline bool factorLdlt(double* a, int n) {
  for (int j = 0; j < n; ++j) {
    double d = a[j + j * n];
    for (int k = 0; k < j; ++k) d -= a[j + k * n] * a[j + k * n] * a[k + k * n];
    if (!(d > 0.0)) return false;
    a[j + j * n] = d;
    eliminateBelow(a, n, j);
  }
  return true;
}

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
