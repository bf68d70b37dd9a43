// The small least-squares solves of the start search
// (fitting/small_least_squares.h): Cholesky, and the bounded problem
// min 1/2 x^T G x - b^T x, x >= lo, checked against solutions worked by
// hand (the optimality conditions: G x = b on the free entries, and the
// gradient pointing out of the bounds on the others).
#include "fitting/small_least_squares.h"

#include <gtest/gtest.h>

namespace clothfit {
namespace {

TEST(SmallLeastSquares, CholeskySolvesAndRefusesASingularSystem) {
  const double g[] = {4, 2, 2, 3};
  const double b[] = {2, 5};
  double x[2];
  ASSERT_TRUE(SolveCholesky(g, b, 2, x));
  EXPECT_NEAR(x[0], -0.5, 1e-15);  // 4 (-0.5) + 2 (2) = 2
  EXPECT_NEAR(x[1], 2.0, 1e-15);   // 2 (-0.5) + 3 (2) = 5
  const double singular[] = {1, 1, 1, 1};
  EXPECT_FALSE(SolveCholesky(singular, b, 2, x));
}

TEST(SmallLeastSquares, InsideTheBoundsIsTheUnconstrainedSolution) {
  const double g[] = {4, 2, 2, 3};
  const double b[] = {2, 5};
  const double lo[] = {-1, 0};
  double x[2];
  ASSERT_TRUE(SolveAboveBounds(g, b, lo, 2, x));
  EXPECT_NEAR(x[0], -0.5, 1e-14);
  EXPECT_NEAR(x[1], 2.0, 1e-14);
}

// G = [[2, 1], [1, 2]], b = (1, -2): unconstrained (4/3, -5/3). With x >= 0
// the second entry is on its bound, the first solves 2 x0 = 1, and the
// gradient of the second, b1 - G10 x0 = -2.5, keeps it there.
TEST(SmallLeastSquares, AnActiveBoundMovesTheOtherEntries) {
  const double g[] = {2, 1, 1, 2};
  const double b[] = {1, -2};
  const double lo[] = {0, 0};
  double x[2];
  ASSERT_TRUE(SolveAboveBounds(g, b, lo, 2, x));
  EXPECT_NEAR(x[0], 0.5, 1e-15);
  EXPECT_EQ(x[1], 0.0);
}

// Lower bounds other than 0: with G = I and b = 0 every entry rests on its
// bound; with b = (3, 0, 0.2) the first leaves it, the others do not.
TEST(SmallLeastSquares, NonZeroLowerBounds) {
  const double g[] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double lo[] = {0.5, 1e-6, 0.25};
  double x[3];
  const double zero[] = {0, 0, 0};
  ASSERT_TRUE(SolveAboveBounds(g, zero, lo, 3, x));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(x[i], lo[i]);
  const double b[] = {3, 0, 0.2};
  ASSERT_TRUE(SolveAboveBounds(g, b, lo, 3, x));
  EXPECT_NEAR(x[0], 3.0, 1e-15);
  EXPECT_EQ(x[1], 1e-6);
  EXPECT_EQ(x[2], 0.25);
}

// A case where an entry leaves the free set on the way (Lawson and
// Hanson's inner loop): G = [[10, 2, 2], [2, 15, -14], [2, -14, 17]],
// b = (3, 2, 2). The first entry has the steepest gradient and enters
// first; once the other two are free it would turn negative, and the
// solution is x = (0, 62/59, 58/59), the first entry's gradient there
// 3 - 2 (62 + 58) / 59 = -63/59 < 0.
TEST(SmallLeastSquares, EntriesLeaveTheFreeSetWhenTheyReachTheirBound) {
  const double g[] = {10, 2, 2, 2, 15, -14, 2, -14, 17};
  const double b[] = {3, 2, 2};
  const double lo[] = {0, 0, 0};
  double x[3];
  ASSERT_TRUE(SolveAboveBounds(g, b, lo, 3, x));
  EXPECT_EQ(x[0], 0.0);
  EXPECT_NEAR(x[1], 62.0 / 59.0, 1e-14);
  EXPECT_NEAR(x[2], 58.0 / 59.0, 1e-14);
}

}  // namespace
}  // namespace clothfit
