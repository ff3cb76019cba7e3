// The joint torques a reference asks for, by inverse dynamics of its own frames (MuJoCo mj_inverse
// on central differences, URDF masses, inertias and armature). For a joint with no foot below it
// (waist, arms, head) this is the torque the joint must give whatever the floor does, so a ratio
// above 1 to its effort limit is a frame no controller can track; a leg joint's torque depends on
// the contact forces and is left out. Prints per joint the largest |tau| / effort limit and when,
// on the reference's timeline (a com-plan lead-in included). For diagnosing the check's
// torque-saturation violations: G1's PyMO walk asks its waist for 2.2-2.5 times its 35 N m before
// the check falls there (2026-12-07).
// Usage: probe_joint_torques ROBOT REFERENCE(.csv with meta | .npz) [fps for a plain CSV] [until s]

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/sim/reference_signal.hpp"

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
    const ReferenceSignal signal(*model, data, ref, 0.0);
    const MatX& q = signal.q_frames();
    const int T = static_cast<int>(q.cols());
    const double fps = ref.fps;
    const mjModel* m = model->mj();
    mjData* d = data.mj();
    // Joints with a foot below them: their torque depends on the contact forces.
    std::vector<bool> carries_foot(model->joints().size(), false);
    for (const Sole& sole : model->soles())
      for (int l = sole.link; l >= 0 && model->links()[static_cast<std::size_t>(l)].parent_joint >= 0;) {
        const int j = model->links()[static_cast<std::size_t>(l)].parent_joint;
        carries_foot[static_cast<std::size_t>(j)] = true;
        l = model->joints()[static_cast<std::size_t>(j)].parent_link;
      }
    const std::size_t J = model->joints().size();
    std::vector<double> worst(J, 0.0), when(J, 0.0);
    for (int f = 1; f + 1 < T && f / fps <= until_s; ++f) {
      const VecX v0 = difference(*model, q.col(f - 1), q.col(f), 1.0 / fps), v1 = difference(*model, q.col(f), q.col(f + 1), 1.0 / fps);
      const VecX v = 0.5 * (v0 + v1), a = (v1 - v0) * fps;
      for (int i = 0; i < m->nq; ++i) d->qpos[i] = q(i, f);
      for (int i = 0; i < m->nv; ++i) {
        d->qvel[i] = v[i];
        d->qacc[i] = a[i];
      }
      mj_inverse(m, d);
      for (std::size_t j = 0; j < J; ++j) {
        const Joint& joint = model->joints()[j];
        if (joint.dof_index < 0 || joint.type == JointType::Floating || carries_foot[j] || joint.effort_limit <= 0) continue;
        const double ratio = std::abs(d->qfrc_inverse[joint.dof_index]) / joint.effort_limit;
        if (ratio > worst[j]) {
          worst[j] = ratio;
          when[j] = f / fps;
        }
      }
    }
    for (std::size_t j = 0; j < J; ++j) {
      const Joint& joint = model->joints()[j];
      if (joint.dof_index < 0 || joint.type == JointType::Floating || carries_foot[j] || joint.effort_limit <= 0) continue;
      std::printf("%-28s %6.2f x its effort limit (%.0f N m) at %.2f s\n", joint.name.c_str(), worst[j], joint.effort_limit, when[j]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
