// Probe of what the check's walking controller can walk (issue 15): the synthetic walk of
// synthetic_references.hpp (holding the standing pose, WalkOptions::hold_standing_pose) over a grid
// of step lengths, step durations and COM heights, each checked with the default options. A real
// clip's one verdict moves with modest changes of the reference or the controller (the real walks
// sit at the edge of what the controller can do), so a controller change is better judged on a
// graded measure: how far the passing region reaches.
//
// Usage: probe_walk_envelope ROBOT [--steps N] [--reference FILE ...]
//   --steps N             steps per walk (default 8)
//   --reference FILE ...  instead of the grid, where these references (with a contact schedule in
//                         their meta.json or NPZ) lie on it: per touchdown, the new stance sole's advance
//                         past the other sole along the root's travel over the last two steps, and
//                         the time since the previous touchdown (median and largest advance)
// Prints one table per COM drop (0, 4, 8 cm below standing): rows step duration, columns step
// length (advance of the swing foot past the other foot); "ok" passes, a number is the fall time
// [s], "kin" marks a walk the generator could not make (its feet or its COM miss their targets by
// more than 2 mm / 5 mm, or the check finds its stance feet off its floor: a step too long for the
// legs at that COM height; not the controller's failure), "err" no reference at all, "x" another
// failing violation. A "*" marks a walk whose waist or arms the generator had to move more than
// 0.25 rad from standing to hold the COM at that height with the legs at full stretch: the walk
// asked for, but not a clean one.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/reference/synthetic_references.hpp"
#include "retarget/sim/dynamics_check.hpp"

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Step lengths and durations of a reference, measured as the grid's walks are parameterised.
void print_steps(const rt::RobotModel& model, const std::string& path) {
  using namespace rt;
  const Reference ref = read_reference_for(model, path, 0, "");
  if (ref.contact[0].empty()) throw InputError(path, "no contact schedule");
  const ReferenceRobotMap map(model, ref, path);
  RobotData data(model);
  auto sole = [&](int frame, int foot) {
    update_kinematics(model, data, map.q(ref, frame));
    const Sole& s = model.soles()[static_cast<std::size_t>(foot)];
    return Vec2((link_pose(model, data, s.link) * s.p_L_center).head<2>());
  };
  // The direction of travel over two steps (the root's sway to each stance foot cancels).
  std::vector<double> lengths, durations;
  std::vector<int> touchdowns;
  for (int k = 1; k < ref.num_frames(); ++k) {
    for (int f = 0; f < 2; ++f) {
      const auto fi = static_cast<std::size_t>(f), gi = static_cast<std::size_t>(1 - f);
      if (!(ref.contact[fi][static_cast<std::size_t>(k)] && !ref.contact[fi][static_cast<std::size_t>(k - 1)] &&
            ref.contact[gi][static_cast<std::size_t>(k)]))
        continue;
      const std::size_t n = touchdowns.size();
      if (n >= 2) {
        const Vec2 travel = (ref.root_pos_W.col(k) - ref.root_pos_W.col(touchdowns[n - 2])).head<2>();
        if (travel.norm() > 0.05) {
          lengths.push_back((sole(k, f) - sole(k, 1 - f)).dot(travel.normalized()));
          durations.push_back((k - touchdowns[n - 1]) / ref.fps);
        }
      }
      touchdowns.push_back(k);
    }
  }
  const double longest = lengths.empty() ? 0 : *std::max_element(lengths.begin(), lengths.end());
  std::printf("%s: %zu steps, advance median %.2f m (largest %.2f m), step median %.2f s\n", path.c_str(), lengths.size(),
              median(lengths), longest, median(durations));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ROBOT [--steps N] [--reference FILE ...]\n", argv[0]);
    return 2;
  }
  int steps = 8;
  std::vector<std::string> references;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--reference") == 0) {
      while (i + 1 < argc && argv[i + 1][0] != '-') references.push_back(argv[++i]);
    } else if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) {
      steps = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "unknown option '%s'\n", argv[i]);
      return 2;
    }
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    if (!references.empty()) {
      for (const std::string& path : references) print_steps(*model, path);
      return 0;
    }
    const DynamicsCheckOptions o = default_check_options(*model);
    const double lengths[] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
    const double durations[] = {0.4, 0.5, 0.6, 0.8};
    int passed = 0, controller_cases = 0, clean_passed = 0, clean_cases = 0;
    constexpr double kFootMiss_m = 0.002, kComMiss_m = 0.005, kUpperBody_rad = 0.25;
    for (const double drop : {0.0, 0.04, 0.08}) {
      std::printf("%s, COM %.0f cm below standing: step length [m] ->\n  step [s]", argv[1], drop * 100);
      for (double l : lengths) std::printf(" %7.2f", l);
      std::printf("\n");
      for (const double step_s : durations) {
        std::printf("  %8.2f", step_s);
        for (const double length : lengths) {
          WalkOptions w;
          w.steps = steps;
          w.step_s = step_s;
          w.double_support_s = 0.2 * step_s;
          w.step_length_m = length;
          w.com_drop_m = drop;
          w.hold_standing_pose = true;
          std::string cell;
          try {
            WalkReport met;
            const Reference reference = walk_reference(*model, w, &met);
            bool kinematic = met.max_foot_miss_m > kFootMiss_m || met.max_com_miss_m > kComMiss_m;
            const DynamicsCheckResult r = kinematic ? DynamicsCheckResult{} : run_dynamics_check(*model, reference, o);
            for (const Violation& v : r.violations) kinematic |= v.kind == ViolationKind::StanceOffFloor;
            if (kinematic) {
              cell = "kin";
            } else {
              const bool clean = met.max_upper_body_rad <= kUpperBody_rad;
              ++controller_cases;
              clean_cases += clean;
              if (r.passed) {
                cell = "ok";
                ++passed;
                clean_passed += clean;
              } else {
                cell = r.fell ? format("%.2f", r.fall_time_s) : "x";
              }
              if (!clean) cell += "*";
            }
          } catch (const std::exception&) {
            cell = "err";  // no reference at all (the generator's plan failed)
          }
          std::printf(" %7s", cell.c_str());
          std::fflush(stdout);
        }
        std::printf("\n");
      }
    }
    std::printf("%s: %d of %d walks the generator could make pass; %d of the %d without a \"*\"\n", argv[1], passed,
                controller_cases, clean_passed, clean_cases);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
