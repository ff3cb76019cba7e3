// Writes the synthetic references of synthetic_references.hpp as CSV + meta.json, so that they can
// be checked with `retarget validate` like any reference (issue 15's synthetic walk is generated so).
// Usage: make_synthetic_reference ROBOT walk|foot-lift OUT_STEM [steps step_s double_support_s step_length_m com_drop_m hold_standing_pose]
//   e.g. make_synthetic_reference g1 walk /tmp/walk  ->  /tmp/walk.csv, /tmp/walk.meta.json

#include <cstdio>
#include <cstdlib>
#include <string>

#include "retarget/core/error.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/reference_io.hpp"
#include "retarget/reference/synthetic_references.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s ROBOT walk|foot-lift OUT_STEM [steps step_s double_support_s step_length_m com_drop_m hold_standing_pose(0|1)]\n", argv[0]);
    return 2;
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    const std::string kind = argv[2];
    Reference ref;
    if (kind == "walk") {
      WalkOptions w;
      if (argc > 4) w.steps = std::atoi(argv[4]);
      if (argc > 5) w.step_s = std::atof(argv[5]);
      if (argc > 6) w.double_support_s = std::atof(argv[6]);
      if (argc > 7) w.step_length_m = std::atof(argv[7]);
      if (argc > 8) w.com_drop_m = std::atof(argv[8]);
      if (argc > 9) w.hold_standing_pose = std::atoi(argv[9]) != 0;
      WalkReport met;
      ref = walk_reference(*model, w, &met);
      std::fprintf(stderr, "walk met its targets to: feet %.4f m, COM %.4f m; waist and arms within %.3f rad of standing\n",
                   met.max_foot_miss_m, met.max_com_miss_m, met.max_upper_body_rad);
    } else if (kind == "foot-lift") {
      ref = foot_lift_reference(*model);
    } else {
      std::fprintf(stderr, "unknown reference kind '%s' (walk, foot-lift)\n", kind.c_str());
      return 2;
    }
    for (const std::string& p : write_reference(argv[3], ref, {ReferenceFormat::Csv})) std::printf("%s\n", p.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
