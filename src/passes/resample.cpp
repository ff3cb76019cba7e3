#include "retarget/passes/resample.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace {

// A stance run of the source that no export frame samples (shorter than an export frame, or after
// the last one: a touchdown at the clip's last source frame) is kept on the export frame nearest
// to it, so that the exported schedule has every touchdown the source has.
void keep_unsampled_stances(const std::vector<std::uint8_t>& contact_in, const std::vector<int>& nearest, double fps_in,
                            double fps_out, std::vector<std::uint8_t>& contact_out) {
  const int T_in = static_cast<int>(contact_in.size()), T_out = static_cast<int>(contact_out.size());
  std::vector<std::uint8_t> sampled(static_cast<std::size_t>(T_in), 0);
  for (int i : nearest) sampled[static_cast<std::size_t>(i)] = 1;
  for (int b = 0; b < T_in;) {
    if (!contact_in[static_cast<std::size_t>(b)]) {
      ++b;
      continue;
    }
    int e = b;
    bool seen = false;
    for (; e < T_in && contact_in[static_cast<std::size_t>(e)]; ++e) seen = seen || sampled[static_cast<std::size_t>(e)];
    if (!seen) {
      const double t_mid = 0.5 * (b + e - 1) / fps_in;
      contact_out[static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(t_mid * fps_out)), 0, T_out - 1))] = 1;
    }
    b = e;
  }
}

}  // namespace

Reference resample_motion(const RobotModel& model, const RobotMotion& motion, const ContactSchedule& contacts,
                          const Mat3X& com_W, const Eigen::Matrix2Xd& cop_W, double fps_out) {
  check_frame_rate(fps_out, "--fps", "the output frame rate", kMinFrameRate_hz, kMaxOutputFrameRate_hz);
  const int T = motion.num_frames();
  RT_DEMAND(T > 0 && motion.fps > 0, "resample: empty motion");
  const double duration = (T - 1) / motion.fps;
  const int T_out = static_cast<int>(std::floor(duration * fps_out + 1e-9)) + 1;
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
  if (has_contacts)
    for (auto& c : ref.contact) c.resize(static_cast<std::size_t>(T_out));
  if (com_W.cols() == T) ref.com_W.resize(3, T_out);
  if (cop_W.cols() == T) ref.cop_W.resize(2, T_out);

  std::vector<int> nearest(static_cast<std::size_t>(T_out));  // the source frame each export frame's labels come from
  for (int k = 0; k < T_out; ++k) {
    const double s = std::min(k / fps_out * motion.fps, static_cast<double>(T - 1));
    const int i = std::min(static_cast<int>(std::floor(s)), T - 1);
    const int j = std::min(i + 1, T - 1);
    const double a = s - i;
    const auto qi = motion.q.col(i), qj = motion.q.col(j);
    ref.root_pos_W.col(k) = (1 - a) * qi.head<3>() + a * qj.head<3>();
    const Quat Qi(qi[3], qi[4], qi[5], qi[6]), Qj(qj[3], qj[4], qj[5], qj[6]);
    ref.root_quat_W[static_cast<std::size_t>(k)] = model.root_link_orientation(Qi.slerp(a, Qj).normalized());
    for (int c = 0; c < J; ++c) {
      const int row = 7 + order[static_cast<std::size_t>(c)];
      ref.joint_pos(c, k) = (1 - a) * qi[row] + a * qj[row];
    }
    nearest[static_cast<std::size_t>(k)] = a < 0.5 ? i : j;
    if (has_contacts)
      for (int foot = 0; foot < 2; ++foot)
        ref.contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(k)] =
            contacts.in_contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(nearest[static_cast<std::size_t>(k)])];
    if (ref.com_W.cols() == T_out) ref.com_W.col(k) = (1 - a) * com_W.col(i) + a * com_W.col(j);
    if (ref.cop_W.cols() == T_out) ref.cop_W.col(k) = (1 - a) * cop_W.col(i) + a * cop_W.col(j);
  }
  if (has_contacts)
    for (int foot = 0; foot < 2; ++foot)
      keep_unsampled_stances(contacts.in_contact[static_cast<std::size_t>(foot)], nearest, motion.fps, fps_out,
                             ref.contact[static_cast<std::size_t>(foot)]);
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
