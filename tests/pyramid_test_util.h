// Comparing count pyramids in tests.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "io/count_pyramid.h"

namespace clothfit {
namespace testing_util {

// Expects the same levels, sizes and counts at every texel of every level.
inline void ExpectSamePyramid(const CountPyramid& a, const CountPyramid& b) {
  ASSERT_EQ(a.levels(), b.levels());
  ASSERT_EQ(a.channels(), b.channels());
  std::vector<double> ca(a.channels()), cb(b.channels());
  for (int level = 0; level < a.levels(); ++level) {
    ASSERT_EQ(a.width(level), b.width(level));
    ASSERT_EQ(a.height(level), b.height(level));
    for (int y = 0; y < a.height(level); ++y) {
      for (int x = 0; x < a.width(level); ++x) {
        a.Counts(level, x, y, ca.data());
        b.Counts(level, x, y, cb.data());
        EXPECT_EQ(ca, cb) << "level " << level << " texel " << x << "," << y;
      }
    }
  }
}

}  // namespace testing_util
}  // namespace clothfit
