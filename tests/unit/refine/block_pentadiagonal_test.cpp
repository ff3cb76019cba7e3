// The smooth correction's linear solver (src/refine/smooth_correction.hpp): the in-place block
// Cholesky of a symmetric positive definite block pentadiagonal system against a dense LLT of the
// same matrix, and its refusal of an indefinite one.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "src/refine/smooth_correction.hpp"

namespace rt::refine {
namespace {

struct Banded {
  std::vector<MatX> D, E, F;  // A(f, f), A(f+1, f), A(f+2, f)
  MatX dense;
};

// A = B Bᵀ + I with B block lower triangular of bandwidth 2: SPD and block pentadiagonal.
Banded random_system(int T, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const int N = T * n;
  MatX B = MatX::Zero(N, N);
  for (int f = 0; f < T; ++f)
    for (int g = std::max(0, f - 2); g <= f; ++g)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) B(f * n + i, g * n + j) = normal(rng);
  Banded s;
  s.dense = B * B.transpose() + MatX::Identity(N, N);
  for (int f = 0; f < T; ++f) {
    s.D.push_back(s.dense.block(f * n, f * n, n, n));
    if (f + 1 < T) s.E.push_back(s.dense.block((f + 1) * n, f * n, n, n));
    if (f + 2 < T) s.F.push_back(s.dense.block((f + 2) * n, f * n, n, n));
  }
  return s;
}

TEST(BlockPentadiagonal, MatchesADenseCholesky) {
  for (const auto& [T, n] : {std::pair<int, int>{1, 3}, {2, 4}, {7, 5}, {40, 6}}) {
    Banded s = random_system(T, n, static_cast<unsigned>(T * 31 + n));
    std::mt19937 rng(7);
    std::normal_distribution<double> normal;
    VecX rhs(T * n);
    for (Eigen::Index i = 0; i < rhs.size(); ++i) rhs[i] = normal(rng);
    std::vector<VecX> b;
    for (int f = 0; f < T; ++f) b.push_back(rhs.segment(f * n, n));
    ASSERT_TRUE(solve_block_pentadiagonal(s.D, s.E, s.F, b)) << "T " << T << ", n " << n;
    const VecX expected = s.dense.llt().solve(rhs);
    for (int f = 0; f < T; ++f)
      EXPECT_LT((b[static_cast<std::size_t>(f)] - expected.segment(f * n, n)).cwiseAbs().maxCoeff(), 1e-9 * (1 + expected.cwiseAbs().maxCoeff()))
          << "T " << T << ", n " << n << ", frame " << f;
  }
}

TEST(BlockPentadiagonal, OnlyTheLowerTriangleOfTheDiagonalBlocksIsRead) {
  Banded s = random_system(5, 4, 3);
  Banded t = s;
  for (MatX& D : t.D) D.triangularView<Eigen::StrictlyUpper>().setConstant(1e9);  // garbage above
  std::vector<VecX> b(5, VecX::Ones(4)), c = b;
  ASSERT_TRUE(solve_block_pentadiagonal(s.D, s.E, s.F, b));
  ASSERT_TRUE(solve_block_pentadiagonal(t.D, t.E, t.F, c));
  for (std::size_t f = 0; f < b.size(); ++f) EXPECT_EQ(b[f], c[f]);
}

TEST(BlockPentadiagonal, RefusesAnIndefiniteSystem) {
  Banded s = random_system(6, 3, 11);
  s.D[4] -= 1e6 * MatX::Identity(3, 3);
  std::vector<VecX> b(6, VecX::Ones(3));
  EXPECT_FALSE(solve_block_pentadiagonal(s.D, s.E, s.F, b));
}

}  // namespace
}  // namespace rt::refine
