// Violation bookkeeping: spans from a tracked condition, and the explanation a fall gets from the
// warnings just before it.

#include "retarget/sim/violations.hpp"

#include <gtest/gtest.h>

namespace rt {
namespace {

TEST(Violations, FallIsExplainedByTheWarningsJustBeforeIt) {
  std::vector<Violation> v = {
      {ViolationKind::FootSlip, 0.2, 0.3, 0.5, "m/s", "left foot sole slides at 0.500 m/s"},  // long before: not listed
      {ViolationKind::CopNearEdge, 1.2, 1.4, 0.001, "m", "COP 0.001 m outside the support polygon's edge"},
      {ViolationKind::CopNearEdge, 1.45, 1.55, 0.002, "m", "COP 0.002 m outside the support polygon's edge"},
      {ViolationKind::TorqueSaturation, 1.3, 1.35, 1.5, "ratio", "knee at 1.50x its effort limit"},
      {ViolationKind::TorqueSaturation, 1.4, 1.45, 2.5, "ratio", "ankle at 2.50x its effort limit"},
      {ViolationKind::Fall, 1.6, 1.6, 1.0, "", "trunk tilted 45.0 deg"},
  };
  explain_fall(v, 0.5);
  EXPECT_EQ(v.back().detail,
            "trunk tilted 45.0 deg; in the 0.5 s before: COP at the support's edge 0.30 s; "
            "torque-saturation 0.10 s (ankle at 2.50x its effort limit)");
  // Nothing before the fall: the detail is left as it was; no fall: nothing changes.
  std::vector<Violation> alone = {{ViolationKind::Fall, 1.0, 1.0, 1.0, "", "COM height 0.3 m below 0.35 m"}};
  explain_fall(alone, 0.5);
  EXPECT_EQ(alone[0].detail, "COM height 0.3 m below 0.35 m");
  std::vector<Violation> none = {{ViolationKind::FootSlip, 0.2, 0.3, 0.5, "m/s", "x"}};
  explain_fall(none, 0.5);
  EXPECT_EQ(none[0].detail, "x");
}

TEST(Violations, TrackerEmitsSpansLongerThanItsMinimum) {
  std::vector<Violation> out;
  ViolationTracker t(ViolationKind::JointLimit, "rad", 0.05);
  for (int i = 0; i <= 100; ++i) {
    const double s = i * 0.01;
    const bool on = (s >= 0.10 && s < 0.13) || (s >= 0.50 && s < 0.70);
    t.update(s, on, on ? s : 0, on ? "j" : "", out);
  }
  t.finish(1.0, out);
  ASSERT_EQ(out.size(), 1u);  // the 0.03 s span is below the minimum
  EXPECT_NEAR(out[0].start_s, 0.50, 1e-9);
  EXPECT_NEAR(out[0].end_s, 0.69, 1e-9);
  EXPECT_NEAR(out[0].magnitude, 0.69, 1e-9);
}

}  // namespace
}  // namespace rt
