// How stretched each leg of a reference is, frame by frame: the distance from the hip (the
// origin of the leg's movable joint nearest the root) to the ankle (that of the joint nearest the
// sole) as a fraction of the same distance at the neutral pose (the leg straight), with the
// reference's contact labels and the root's horizontal acceleration. For
// diagnosing where a reference's root is held back or jerked by a leg at the end of its reach.
// Usage: probe_leg_reach ROBOT REFERENCE(.csv with meta | .npz) [fps for a plain CSV]

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>

#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/leg_ends.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ROBOT REFERENCE [fps]\n", argv[0]);
    return 2;
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    const Reference ref = read_reference_for(*model, argv[2], argc > 3 ? std::atof(argv[3]) : 0);
    RobotData data(*model);
    const MatX q = ReferenceRobotMap(*model, ref, "reference").q_all(ref);
    const std::array<LegEnds, 2> legs = leg_ends(*model);
    for (const LegEnds& leg : legs)
      if (leg.hip_link < 0 || leg.hip_link == leg.ankle_link) throw std::runtime_error("a sole has no leg of two joints above it");
    std::printf("frame  t[s]  L R   left_reach right_reach  root_acc_xy[m/s2]\n");
    const Eigen::Index T = q.cols();
    for (Eigen::Index f = 0; f < T; ++f) {
      update_kinematics(*model, data, q.col(f));
      std::array<double, 2> r{};
      for (std::size_t k = 0; k < 2; ++k)
        r[k] = hip_ankle_distance_m(*model, data, legs[k]) / legs[k].length_m;
      double acc = 0;
      if (f > 0 && f + 1 < T) acc = (q.col(f + 1).head<2>() - 2 * q.col(f).head<2>() + q.col(f - 1).head<2>()).norm() * ref.fps * ref.fps;
      const auto fs = static_cast<std::size_t>(f);
      const bool l = ref.has_contacts() && ref.contact[0][fs], rr = ref.has_contacts() && ref.contact[1][fs];
      std::printf("%5ld %6.3f  %c %c   %6.3f %6.3f   %6.1f\n", static_cast<long>(f), f / ref.fps, l ? 'S' : '-', rr ? 'S' : '-', r[0], r[1], acc);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
