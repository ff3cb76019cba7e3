// Scores an exported reference with the current kinematic metrics (design.md §6, quality.hpp), so
// that references written by another build (or another tool, with a meta.json contact schedule)
// can be compared with this one's on the same definitions: foot metrics with the reference's own
// contact labels, landmark error at the exported frames against the clip's scaled landmarks.
//
//   score_reference ROBOT CLIP REFERENCE.csv|.npz [SOURCE_FPS] [--contacts OURS.csv|.npz] [--label-contacts]
//
// --label-contacts labels the reference's contacts from its own foot heights and speeds (as
// `validate` does for a file without a schedule) instead.
// --contacts takes the contact schedule (and, for a plain third-party CSV without meta.json, the
// frame rate) from another reference of the same clip, e.g. ours: both are then scored on the
// same stance phases (Unitree's LAFAN1 CSVs have no schedule).
//
// Prints one line: landmark_median_m drift_max_m heel_drift_max_m yaw_max_deg tilt_max_deg
// height_max_m lowest_point_m swing_frames_low frames_without_stance velocity_violations (frames x
// joints at the reference's own rate; the convert summary counts them at the source rate)
// skating_p95_m penetration_max_m frame0_tilt_deg jitter_rad_s3 (at the reference's rate)
// zmp_near zmp_single_near zmp_inside zmp_outside_max_m (ZMP fractions over stance frames within
// 1 cm of / inside the support, single support for the second).
// With SCORE_ZMP_CSV=FILE set, also writes per frame: t, contact left/right, COM x y z, ZMP x y and
// the ZMP's signed distance from the support polygon (NaN in flight), centroidal angular momentum x y.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_data.hpp"
#include "retarget/model/robot_model.hpp"
#include "support/reference_score.hpp"
#include "retarget/motion/load_motion.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/passes/registry.hpp"
#include "retarget/passes/stance_support.hpp"
#include "retarget/pipeline/pipeline.hpp"
#include "retarget/reference/reference_io.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  std::vector<std::string> args;
  std::string contacts_path;
  bool label_contacts = false;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--label-contacts") {
      label_contacts = true;
    } else if (std::string(argv[i]) == "--contacts" && i + 1 < argc) {
      contacts_path = argv[++i];
    } else {
      args.push_back(argv[i]);
    }
  }
  if (args.size() < 3) {
    std::fprintf(stderr, "usage: score_reference ROBOT CLIP REFERENCE [SOURCE_FPS] [--contacts OURS.csv]\n");
    return 2;
  }
  try {
    const auto model = RobotModel::load(args[0]);
    MotionLoadOptions load;
    if (args.size() > 3) load.source_fps = std::atof(args[3].c_str());
    Clip clip;
    clip.human = load_motion(args[1], load);
    RobotData data(*model);
    (void)Pipeline::parse("retime,scale", builtin_passes()).run(clip, model.get(), &data);
    ReferenceReadOptions read;
    Reference schedule;
    if (!contacts_path.empty()) {
      schedule = read_reference(contacts_path);
      read.fps = schedule.fps;
      for (int k : model->export_joint_order())
        read.joint_names.push_back(
            model->joints()[static_cast<std::size_t>(model->movable_joints()[static_cast<std::size_t>(k)])].name);
    }
    Reference ref = read_reference(args[2], read);
    if (!contacts_path.empty()) {
      // The same clip resampled by two tools may differ by a frame at the end (30.0003 Hz LAFAN1
      // files): both are scored on the common frames.
      const int T = std::min(schedule.num_frames(), ref.num_frames());
      if (std::abs(schedule.num_frames() - ref.num_frames()) > 1 + ref.num_frames() / 100)
        throw InputError(contacts_path, "has " + std::to_string(schedule.num_frames()) + " frames, the reference " +
                                            std::to_string(ref.num_frames()));
      ref.root_pos_W.conservativeResize(3, T);
      ref.root_quat_W.resize(static_cast<std::size_t>(T));
      ref.joint_pos.conservativeResize(ref.joint_pos.rows(), T);
      ref.com_W.resize(3, 0);
      ref.cop_W.resize(2, 0);
      ref.contact = schedule.contact;
      for (auto& c : ref.contact) c.resize(static_cast<std::size_t>(T));
    }
    if (label_contacts) {
      Diagnostics ignored;
      ref.contact = label_robot_contacts(*model, data, ReferenceRobotMap(*model, ref, args[2]).q_all(ref), ref.fps, {},
                                         ignored, args[2])
                        .in_contact;
    }
    const std::vector<int>& order = model->export_joint_order();
    const int T = ref.num_frames();
    MatX q(model->nq(), T);
    for (int k = 0; k < T; ++k) {
      q.col(k).head<3>() = ref.root_pos_W.col(k);
      const Quat R = model->root_body_orientation(ref.root_quat_W[static_cast<std::size_t>(k)]);
      q.col(k).segment<4>(3) << R.w(), R.x(), R.y(), R.z();
      for (std::size_t c = 0; c < order.size(); ++c) q(7 + order[c], k) = ref.joint_pos(static_cast<Eigen::Index>(c), k);
    }
    const QualityMetrics m = foot_metrics(*model, data, q, ref.fps, ref.contact);
    if (const char* dump = std::getenv("SCORE_ZMP_CSV"); dump && ref.has_contacts()) {
      const MultibodyZmp zmp = multibody_zmp(*model, data, q, ref.fps);
      FILE* out = std::fopen(dump, "w");
      if (!out) throw std::runtime_error(std::string("cannot write ") + dump);
      std::fprintf(out, "t,left,right,com_x,com_y,com_z,zmp_x,zmp_y,distance,L_x,L_y\n");
      for (int k = 0; k < T; ++k) {
        const std::array<bool, 2> down{{ref.contact[0][static_cast<std::size_t>(k)] != 0, ref.contact[1][static_cast<std::size_t>(k)] != 0}};
        const int a = std::max(k - 1, 0), b = std::min(k + 1, T - 1);
        const VecX v = b > a ? difference(*model, q.col(a), q.col(b), (b - a) / ref.fps) : VecX::Zero(model->nv());
        const Vec3 L = centroidal_momentum(*model, data, q.col(k), v).angular_com_W;
        update_kinematics(*model, data, q.col(k));
        const SupportPolygon poly2 = stance_support_polygon(*model, data, down);
        std::fprintf(out, "%.4f,%d,%d,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f\n", k / ref.fps, down[0], down[1], zmp.com_W(0, k),
                     zmp.com_W(1, k), zmp.com_W(2, k), zmp.zmp_W(0, k), zmp.zmp_W(1, k),
                     poly2.empty() ? NAN : poly2.signed_distance(zmp.zmp_W.col(k)), L.x(), L.y());
      }
      std::fclose(out);
    }
    std::vector<double> errors;
    for (int k = 0; k < T; ++k) {
      const int f = static_cast<int>(std::lround(k * clip.human.fps / ref.fps));  // resample keeps t = 0
      if (f >= clip.human.num_frames) break;
      const double e = frame_landmark_error_m(*model, data, clip.targets, q.col(k), f, nullptr);
      if (std::isfinite(e)) errors.push_back(e);
    }
    std::sort(errors.begin(), errors.end());
    int velocity = 0;
    const VecX& limit = model->velocity_limits();
    for (int k = 1; k < T; ++k)
      for (int i = 0; i < model->nu(); ++i)
        velocity += limit[i] > 0 && std::abs(q(7 + i, k) - q(7 + i, k - 1)) * ref.fps > limit[i] * (1 + 1e-9);
    const test::ReferenceScore score = test::score_with_contacts(*model, ref, ref.contact);
    std::printf("%.4f %.4f %.4f %.2f %.2f %.4f %.4f %d %d %d %.4f %.4f %.2f %.1f %.3f %.3f %.3f %.3f\n",
                errors.empty() ? 0.0 : errors[errors.size() / 2], m.foot_skating_max_m, m.heel_skating_max_m,
                m.stance_yaw_drift_max_deg, m.stance_tilt_max_deg, m.stance_height_max_m, m.lowest_point_m,
                m.swing_frames_low, m.frames_without_stance, velocity, score.feet.foot_skating_p95_m,
                score.feet.penetration_max_m, score.feet.frame0_sole_tilt_deg, score.jitter_rad_s3, m.zmp_near_fraction,
                m.zmp_single_near_fraction, m.zmp_inside_fraction, m.zmp_outside_max_m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "score_reference: %s\n", e.what());
    return 2;
  }
  return 0;
}
