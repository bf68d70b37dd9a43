// The models' parameter tables (models/params.h): every entry agrees with
// the field it describes (one or three channels), its default is valid,
// its fit bounds lie in its valid range, names are unique within a model,
// and unit, meaning and source are given.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "models/evaluate.h"

namespace clothfit {
namespace {

// Whether x lies in the closure of the interval (a fit bound may touch an
// open end only when it is the physical range, e.g. kd in [0, 1]).
bool InClosure(const Interval& i, double x) {
  return std::isfinite(x) && x >= i.lo && x <= i.hi;
}

template <typename P>
void ExpectTableConsistent(const P& defaults, const std::string& model) {
  std::set<std::string> names;
  VisitParamsConst(defaults, [&](const ParamInfo& info, const auto& field) {
    using V = std::decay_t<decltype(field)>;
    const std::string where = model + "." + info.name;
    EXPECT_TRUE(names.insert(info.name).second) << where << ": twice";
    const int channels = std::is_same_v<V, double> ? 1 : 3;
    EXPECT_EQ(info.channels, channels) << where;
    EXPECT_STRNE(info.unit, "") << where;
    EXPECT_STRNE(info.meaning, "") << where;
    EXPECT_STRNE(info.source, "") << where;
    EXPECT_LT(info.fit_lo, info.fit_hi) << where;
    EXPECT_TRUE(InClosure(info.valid, info.fit_lo)) << where;
    EXPECT_TRUE(InClosure(info.valid, info.fit_hi)) << where;
    for (int c = 0; c < info.channels; ++c) {
      EXPECT_TRUE(info.valid.Contains(info.defaults[c]))
          << where << " default " << c;
    }
  });
  // The struct's own defaults are the table's, and valid.
  EXPECT_EQ(ValidateParams(defaults), "") << model;
}

TEST(ParamTables, EveryEntryAgreesWithItsField) {
  ExpectTableConsistent(ThreadParams(), "thread");
  ExpectTableConsistent(SlabParams(), "slab");
  ExpectTableConsistent(HolesParams(), "holes");
  ExpectTableConsistent(LafortuneLobe(), "lafortune lobe");
}

TEST(ParamTables, TheOtherEntriesAreConsistentToo) {
  for (const ParamInfo* info :
       {&kClothCoverage, &kClothOffsets, &kLafortuneDiffuse}) {
    EXPECT_LT(info->fit_lo, info->fit_hi) << info->name;
    EXPECT_TRUE(InClosure(info->valid, info->fit_lo)) << info->name;
    EXPECT_TRUE(InClosure(info->valid, info->fit_hi)) << info->name;
    for (int c = 0; c < info->channels; ++c) {
      EXPECT_TRUE(info->valid.Contains(info->defaults[c])) << info->name;
    }
  }
  EXPECT_EQ(LafortuneParams().diffuse, kLafortuneDiffuse.DefaultRgb<double>());
}

TEST(ParamTables, ValidationNamesTheEntryAndItsRange) {
  ThreadParams t;
  t.gamma_s_deg = -1.0;
  EXPECT_EQ(ValidateParams(t), "gamma_s_deg: must be in [0.01, 90], got -1");
  t = ThreadParams();
  t.albedo.z = std::nan("");
  EXPECT_EQ(ValidateParams(t),
            "albedo: component 2 must be in [0, 1000], got nan");
  LafortuneLobe lobe;
  lobe.cy.x = HUGE_VAL;
  EXPECT_EQ(ValidateParams(lobe),
            "Cy: component 0 must be in [-1e+100, 1e+100], got inf");
}

}  // namespace
}  // namespace clothfit
