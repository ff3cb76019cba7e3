// The joint torques a reference asks for, by inverse dynamics of its own frames
// (model/torque_demand.hpp: the quality metric `torque_demand_*` of a conversion, here for any
// reference and per joint). For a joint with no foot below it (waist, arms, head) this is the
// torque the joint must give whatever the floor does, so a ratio above 1 to its effort limit is a
// frame no controller can track; a leg joint's torque depends on the contact forces and is left
// out. Prints per joint the largest |tau| / effort limit and when, on the reference's timeline (a
// com-plan lead-in included), and the frames over a limit. For diagnosing the check's
// torque-saturation violations: G1's PyMO walk asks its waist for 2.2-2.5 times its 35 N m before
// the check falls there (2026-12-07).
// Usage: probe_joint_torques ROBOT REFERENCE(.csv with meta | .npz) [fps for a plain CSV] [until s]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/torque_demand.hpp"
#include "retarget/reference/robot_mapping.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ROBOT REFERENCE [fps] [until_s]\n", argv[0]);
    return 2;
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    const Reference ref = read_reference_for(*model, argv[2], argc > 3 ? std::atof(argv[3]) : 0);
    const double until_s = argc > 4 ? std::atof(argv[4]) : INFINITY;
    RobotData data(*model);
    MatX q = ReferenceRobotMap(*model, ref, "reference").q_all(ref);
    // Up to until_s, and one frame beyond for the last central difference.
    const auto frames = static_cast<Eigen::Index>(std::min<double>(static_cast<double>(q.cols()), std::floor(until_s * ref.fps) + 2));
    q = q.leftCols(frames).eval();
    const TorqueDemand d = torque_demand(*model, data, q, ref.fps);
    for (int i = 0; i < model->nu(); ++i) {
      if (!d.judged[static_cast<std::size_t>(i)]) continue;
      std::printf("%-28s %6.2f x its effort limit (%.0f N m) at %.2f s\n",
                  model->joints()[static_cast<std::size_t>(model->movable_joints()[static_cast<std::size_t>(i)])].name.c_str(),
                  d.joint_max_ratio[static_cast<std::size_t>(i)], model->effort_limits()[i], d.joint_max_time_s[static_cast<std::size_t>(i)]);
    }
    std::printf("frames over a limit: %d of %d\n", d.frames_over, d.frames);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
