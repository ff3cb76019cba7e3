#include "retarget/passes/resample.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/pipeline/clip_rate.hpp"

namespace rt {

Reference resample_motion(const RobotModel& model, const RobotMotion& motion, const ContactSchedule& contacts,
                          const Mat3X& com_W, const Eigen::Matrix2Xd& cop_W, double fps_out) {
  check_frame_rate(fps_out, "--fps", "the output frame rate", kMinFrameRate_hz, kMaxOutputFrameRate_hz);
  const int T = motion.num_frames();
  RT_DEMAND(T > 0 && motion.fps > 0, "resample: empty motion");
  const int T_out = grid_frames(T, motion.fps, fps_out);
  const std::vector<int>& order = model.export_joint_order();
  const int J = static_cast<int>(order.size());

  Reference ref;
  ref.robot_name = model.name();
  ref.fps = fps_out;
  for (int k : order)
    ref.joint_names.push_back(model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(k)])].name);
  ref.root_pos_W.resize(3, T_out);
  ref.root_quat_W.resize(static_cast<std::size_t>(T_out));
  ref.joint_pos.resize(J, T_out);
  const bool has_contacts = !contacts.empty();
  if (com_W.cols() == T) ref.com_W.resize(3, T_out);
  if (cop_W.cols() == T) ref.cop_W.resize(2, T_out);

  for (int k = 0; k < T_out; ++k) {
    const GridSample g = grid_sample(k, motion.fps, fps_out, T);
    const auto qi = motion.q.col(g.i), qj = motion.q.col(g.j);
    const double a = g.a;
    ref.root_pos_W.col(k) = (1 - a) * qi.head<3>() + a * qj.head<3>();
    const Quat Qi(qi[3], qi[4], qi[5], qi[6]), Qj(qj[3], qj[4], qj[5], qj[6]);
    ref.root_quat_W[static_cast<std::size_t>(k)] = model.root_link_orientation(Qi.slerp(a, Qj).normalized());
    for (int c = 0; c < J; ++c) {
      const int row = 7 + order[static_cast<std::size_t>(c)];
      ref.joint_pos(c, k) = (1 - a) * qi[row] + a * qj[row];
    }
    if (ref.com_W.cols() == T_out) ref.com_W.col(k) = (1 - a) * com_W.col(g.i) + a * com_W.col(g.j);
    if (ref.cop_W.cols() == T_out) ref.cop_W.col(k) = (1 - a) * cop_W.col(g.i) + a * cop_W.col(g.j);
  }
  if (has_contacts)
    for (std::size_t foot = 0; foot < 2; ++foot) ref.contact[foot] = resample_contact(contacts.in_contact[foot], motion.fps, fps_out, T_out);
  return ref;
}

ResamplePass::ResamplePass() { table_.add("fps", options_.fps, "[Hz] output frame rate", {kMinFrameRate_hz, kMaxOutputFrameRate_hz, "Hz"}); }

void ResamplePass::run(Clip& clip, PassContext& ctx) {
  if (clip.motion.num_frames() == 0) throw InputError("--passes", "resample needs the robot motion of the ik pass: put ik before resample");
  clip.reference = resample_motion(ctx.model(), clip.motion, clip.contacts, clip.com_replanned_W, clip.cop_predicted_W,
                                   options_.fps);
  ctx.statistics.set("frames-out", clip.reference.num_frames(), "frames");
  ctx.statistics.set("fps-out", options_.fps, "Hz");
}

}  // namespace rt
