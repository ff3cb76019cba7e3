#include "retarget/passes/com_plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "retarget/core/error.hpp"
#include "retarget/core/gaussian_filter.hpp"
#include "retarget/core/lap_timer.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/smoothstep.hpp"
#include "retarget/ik/foot_down.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/model/sole_geometry.hpp"
#include "retarget/passes/ik_pass.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/passes/stance_support.hpp"
#include "retarget/pipeline/clip_ends.hpp"
#include "retarget/pipeline/clip_rate.hpp"
#include "src/refine/foot_plan.hpp"
#include "src/refine/signal_smoother.hpp"
#include "src/refine/smooth_correction.hpp"

namespace rt {

namespace {

// [m] Height of the lowest corner of a sole rectangle at the sole frame X (W).
double lowest_corner_z(const Iso3& X, const Sole& sole) {
  double z = std::numeric_limits<double>::infinity();
  for (const Vec3& c : sole_corners_W(X, sole)) z = std::min(z, c.z());
  return z;
}

// How far a swing sole's target pose (7-vector: position, quaternion w x y z) must rise so that
// neither its centre nor its lowest corner is lower than in the pose it came from (by a millimetre
// more, the IK's following error): the low-pass also tilts the sole (toe-off, heel strike), which
// lowers a corner while the centre stays up, and refine kept the corners clear of the floor.
double raise_to_clear(const VecX& target, const VecX& original, const Sole& sole) {
  constexpr double kFollowSlack_m = 0.001;
  auto lowest_corner = [&](const VecX& pose) {
    Iso3 X = Iso3::Identity();
    X.translation() = pose.head<3>();
    X.linear() = Quat(pose(3), pose(4), pose(5), pose(6)).normalized().toRotationMatrix();
    return lowest_corner_z(X, sole);
  };
  return std::max(original(2) - target(2), lowest_corner(original) + kFollowSlack_m - lowest_corner(target));
}

// Column of a per-frame signal at time t [s] (linear interpolation, clamped to the clip).
template <class M>
Eigen::Matrix<double, M::RowsAtCompileTime, 1> at_time(const M& cols, double fps, double t) {
  const int T = static_cast<int>(cols.cols());
  const double s = std::clamp(t * fps, 0.0, static_cast<double>(T - 1));
  const int i = std::min(static_cast<int>(s), T - 1), j = std::min(i + 1, T - 1);
  return (1 - (s - i)) * cols.col(i) + (s - i) * cols.col(j);
}

// Cart-table ZMP c − h c̈ per frame, with c̈ the same second differences multibody_zmp uses.
Eigen::Matrix2Xd cart_table_zmp(const Eigen::Matrix2Xd& com_W, const VecX& gain_s2, double fps) {
  const int T = static_cast<int>(com_W.cols());
  Eigen::Matrix2Xd p = com_W;
  if (T < 3) return p;
  for (int f = 0; f < T; ++f) {
    const int i = std::clamp(f, 1, T - 2);
    p.col(f) -= gain_s2[f] * (com_W.col(i + 1) - 2 * com_W.col(i) + com_W.col(i - 1)) * fps * fps;
  }
  return p;
}

// The motion low-passed coordinate by coordinate (σ in samples): root quaternions are first put on
// one hemisphere and renormalised after; joints stay inside their limits (a convex combination).
MatX smooth_motion(const MatX& q, double sigma) {
  MatX aligned = q;
  for (Eigen::Index f = 1; f < q.cols(); ++f)
    if (aligned.col(f).segment<4>(3).dot(aligned.col(f - 1).segment<4>(3)) < 0) aligned.col(f).segment<4>(3) *= -1;
  MatX out = gaussian_filter(aligned, sigma);
  for (Eigen::Index f = 0; f < q.cols(); ++f) out.col(f).segment<4>(3).normalize();
  return out;
}

// Whether `link` is a foot's sole link or hangs below one (toes): its landmarks are held by the sole targets.
bool on_a_foot(const RobotModel& model, int link) {
  for (int l = link; l >= 0;) {
    for (const Sole& s : model.soles())
      if (s.link == l) return true;
    const int j = model.links()[static_cast<std::size_t>(l)].parent_joint;
    l = j < 0 ? -1 : model.joints()[static_cast<std::size_t>(j)].parent_link;
  }
  return false;
}

// ZmpPlanSample::com_weight_scale of a pinned plan sample: far above the ZMP rows' penalty (1e6),
// so the plan keeps the retargeted COM there and bends towards it around.
constexpr double kPinnedComWeightScale = 1e8;
// [m] how far below the floor a collision point may go (issue 13's floor bar).
constexpr double kFloorTolerance_m = 0.002;
// Frames either side of one that gave that keep their input pose too (a repair), or take the stage's
// start back whole (the stage's give-back): a fault's neighbours are seldom far from it.
constexpr int kKeptMargin = 2;
// Times the whole-body stage gives frames back (each pass may leave a fault where its blend begins:
// a frame the stage moved further than the projection back onto the soles can undo).
constexpr int kGiveBackPasses = 6;

struct Follow {
  MatX q;
  int missed_frames = 0;       ///< |COM − plan| > follow tolerance
  double max_miss_m = 0;
  double max_miss_time_s = 0;
  double max_foot_error_m = 0;  ///< largest sole-centre move from its held pose
  std::vector<double> foot_error_m;  ///< per frame: the largest sole-centre move from its held pose
  std::vector<std::uint8_t> kept_as_input;  ///< per frame (empty: none): the input pose kept
};

struct Frames {
  std::vector<std::array<IkTarget, 2>> soles;  ///< held sole poses per frame
  std::vector<SupportPolygon> polygon;         ///< unshrunk support per frame (empty: flight)
};

// Stance frames (those with a polygon; the first and last frame left out, as in the metric) whose
// ZMP lies more than `tolerance_m` outside their support polygon, and the worst distance outside.
struct Score {
  int outside = 0;
  double worst_m = 0;
  bool better_than(const Score& o) const { return outside < o.outside || (outside == o.outside && worst_m < o.worst_m); }
};
// Per foot and frame: how far the sole's centre or heel (the larger) has moved horizontally since
// its stance began (the summary's stance drift, quality.cpp); 0 where the foot swings.
std::array<std::vector<double>, 2> stance_travel(const RobotModel& model, RobotData& data, const MatX& q,
                                                 const std::array<std::vector<std::uint8_t>, 2>& contacts,
                                                 const std::array<Mat3, 2>& R_L_sole) {
  const int T = static_cast<int>(q.cols());
  std::array<std::vector<double>, 2> travel;
  for (auto& t : travel) t.assign(static_cast<std::size_t>(T), 0.0);
  std::array<Vec2, 2> start_centre{}, start_heel{};
  for (int f = 0; f < T; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!contacts[0][fi] && !contacts[1][fi]) continue;
    update_kinematics(model, data, q.col(f));
    for (std::size_t foot = 0; foot < 2; ++foot) {
      if (!contacts[foot][fi]) continue;
      const Sole& sole = model.soles()[foot];
      const Iso3 X = sole_frame_W(model, data, static_cast<int>(foot), R_L_sole[foot]);
      const Vec2 centre = X.translation().head<2>();
      const Vec2 heel = (X * Vec3(-0.5 * sole.size_m.x(), 0, 0)).head<2>();
      if (f == 0 || !contacts[foot][fi - 1]) {
        start_centre[foot] = centre;
        start_heel[foot] = heel;
      }
      travel[foot][fi] = std::max((centre - start_centre[foot]).norm(), (heel - start_heel[foot]).norm());
    }
  }
  return travel;
}

// Per frame, the height of the robot's lowest collision point [m] (negative: below the floor).
std::vector<double> lowest_points(const RobotModel& model, RobotData& data, const MatX& q) {
  std::vector<double> z(static_cast<std::size_t>(q.cols()));
  for (int f = 0; f < q.cols(); ++f) {
    update_kinematics(model, data, q.col(f));
    z[static_cast<std::size_t>(f)] = lowest_collision_point(model, data).z_m;
  }
  return z;
}

Score score_zmp(const std::vector<SupportPolygon>& polygons, const MultibodyZmp& zmp, double tolerance_m) {
  Score s;
  const int T = static_cast<int>(polygons.size());
  for (int f = 1; f + 1 < T; ++f) {
    const SupportPolygon& p = polygons[static_cast<std::size_t>(f)];
    if (p.empty()) continue;
    const double d = zmp_distance_outside(p, zmp, f);
    s.outside += d > tolerance_m;
    s.worst_m = std::max(s.worst_m, d);
  }
  return s;
}

}  // namespace

ComPlanPass::ComPlanPass() {
  table_.add("period", options_.plan.period_s, "[s] planning grid (at most the export period)", {0.001, 0.1, "s"});
  table_.add("margin", options_.margin_m, "[m] the planned ZMP keeps this far inside the support polygon");
  table_.add("ankle_reach", options_.ankle_reach, "plan the ZMP only where each ankle's effort limit holds the COP under the robot's weight");
  table_.add("com_tracking", options_.plan.com_weight, "plan: weight of |c - c_retargeted|^2 [1/m^2]");
  table_.add("jerk", options_.plan.jerk_weight, "plan: weight of |c'''|^2 [s^6/m^2] (2e-8: 3 Hz low-pass)");
  table_.add("flight_acceleration", options_.plan.flight_acceleration_weight, "plan: weight of |c''|^2 on flight samples");
  table_.add("rest_start", options_.plan.rest_at_start, "plan: COM at rest at the first frame");
  table_.add("rest_end", options_.plan.rest_at_end, "plan: COM at rest at the last frame");
  table_.add("lead", options_.lead_s, "[s] standing lead-in / lead-out added where the clip starts / ends moving (0: none)",
             {0, 5, "s"});
  table_.add("lead_speed", options_.lead_speed_mps, "[m/s] COM speed at an end above which the clip counts as moving there",
             {0, 10, "m/s"});
  table_.add("smoothing", options_.smoothing_s, "[s] Gaussian low-pass of the pose, swing soles and COM height the IK follows",
             {0, 1, "s"});
  table_.add("swing_smoothing", options_.swing_smoothing_s, "[s] Gaussian low-pass of the swing soles' trajectories (0: as they are)",
             {0, 1, "s"});
  table_.add("max_offset", options_.max_offset_m, "[m] longest angular-momentum ZMP correction used by the plan");
  table_.add("iterations", options_.iterations, "plan + COM-following rounds of the multibody correction", {0, 100, ""});
  table_.add("repairs", options_.repairs,
             "a round that moves a held sole is re-planned with the COM pinned there, then followed again up to this many "
             "times with the frames that still give left as they came (0: dropped)",
             {0, 20, ""});
  table_.add("pin_window", options_.pin_window_s, "[s] plan samples this near a frame whose held sole gave are pinned",
             {0, 5, "s"});
  table_.add("whole_body_give_back", options_.whole_body_give_back,
             "frames where the whole-body stage breaks a sole take the rounds' motion back (false: such a stage is dropped)");
  table_.add("com_weight", options_.com_weight, "COM-following IK: weight of the COM target");
  table_.add("foot_weight", options_.foot_weight, "COM-following IK: weight holding the soles");
  table_.add("landmark_factor", options_.landmark_factor, "COM-following IK: factor on the other landmarks' weights");
  table_.add("posture_regularization", options_.posture_regularization, "COM-following IK: pull towards the frame's pose");
  table_.add("ik_iterations", options_.ik_iterations, "COM-following IK: iterations per frame", {1, 10000, ""});
  table_.add("velocity_margin", options_.velocity_margin, "fraction of each velocity limit the frame-to-frame bounds keep free");
  table_.add("foot_tolerance", options_.foot_tolerance_m, "[m] a round that moves a held sole further is dropped");
  table_.add("max_landmark_growth", options_.max_landmark_growth_m,
             "[m] a round or stage that grows the landmark error median more is dropped", {0, 10, "m"});
  table_.add("follow_tolerance", options_.follow_tolerance_m, "[m] frames whose COM misses the plan by more are reported");
  table_.add("whole_body_iterations", options_.whole_body_iterations,
             "Gauss-Newton iterations of the whole-body ZMP correction (0: off)", {0, 100, ""});
  table_.add("whole_body_extra_iterations", options_.whole_body_extra_iterations,
             "whole-body stage: further steps while a ZMP, stance or limit row is missed; > 0 also retries a rejected step damped",
             {0, 100, ""});
  table_.add("whole_body_zmp_weight", options_.whole_body_zmp_weight, "whole-body stage: weight of a ZMP row [1/m^2]");
  table_.add("whole_body_smoothing_hz", options_.whole_body_smoothing_hz, "[Hz] whole-body stage: cutoff of its smoothness term",
             {0.1, 100, "Hz"});
  table_.add("fps", options_.export_fps, "[Hz] the export rate, the grid the pass works on (--fps sets it)", {1, 1000, "Hz"});
}

namespace {

// Horizontal COM speed [m/s] over the first (`at_end` false) or last 0.1 s of the motion.
double end_com_speed(const RobotModel& model, RobotData& data, const RobotMotion& motion, bool at_end) {
  const int T = motion.num_frames();
  const int n = std::min(T - 1, std::max(1, static_cast<int>(std::lround(0.1 * motion.fps))));
  if (n < 1) return 0;
  const int a = at_end ? T - 1 - n : 0, b = a + n;
  update_kinematics(model, data, motion.q.col(a));
  const Vec3 c_a = com_position(model, data);
  update_kinematics(model, data, motion.q.col(b));
  const Vec3 c_b = com_position(model, data);
  return (c_b - c_a).head<2>().norm() * motion.fps / n;
}

// Where a lead (`frames` frames held at the clip's start, or at its end with `at_end`) stands on
// one foot, it is made to stand on both: the airborne foot is put down flat below where it is
// (put_foot_down; the root may lower), and lifted into the clip's first pose (lowered from its last)
// over the lead's last (first) frames, labelled in swing there. A reference then starts and stops
// where a robot is put down and left, standing on both feet, rather than holding a one-legged
// balance for the whole lead that the clip never asked for. The transition lasts the swing guard
// (0.1 s), longer where the root must rise or drop by more than 2 m/s² allow (a quintic smoothstep
// peaks at about 6 h / D²), and at most half the lead. Its frames are solved by IK: the stance sole
// where it is, the moving one on a smoothstep from the floor to its end pose, its lowest corner
// raised towards 1.5 cm (plus 1 mm) up as the swing gets further from its lift-off or touchdown,
// all of it beyond the guard (issue 13's swing bar), the rest pulled towards the joint-space blend.
// A transition that misses a sole by more than `max_corner_miss_m` leaves the lead on one foot.
// Returns what was done, for the statistics.
std::string stand_lead_on_both_feet(const RobotModel& model, RobotData& data, Clip& work, int frames, bool at_end,
                                    double max_corner_miss_m) {
  constexpr double kTransitionMin_s = 0.1, kRootAccel_mps2 = 2.0, kGuard_s = 0.1, kClearance_m = 0.015, kSlack_m = 0.001;
  RobotMotion& motion = work.motion;
  const int T = motion.num_frames();
  if (work.contacts.empty() || frames < 2 || T < frames + 1) return "";
  const int end = at_end ? T - frames - 1 : frames;  // the clip's own end frame
  auto& contact = work.contacts.in_contact;
  const bool left = contact[0][static_cast<std::size_t>(end)] != 0, right = contact[1][static_cast<std::size_t>(end)] != 0;
  if (left == right) return "";
  const int foot = left ? 1 : 0, stance = 1 - foot;  // the airborne one, the standing one
  const auto fi = static_cast<std::size_t>(foot), si = static_cast<std::size_t>(stance);
  const char* name = foot == 0 ? "left" : "right";
  const VecX q_end = motion.q.col(end);
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);  // (moves `data`)
  update_kinematics(model, data, q_end);
  const Iso3 X_stance = sole_frame_W(model, data, stance, R_L_sole[si]);
  const Iso3 X_up = sole_frame_W(model, data, foot, R_L_sole[fi]);
  const double floor_z = lowest_sole_corner_z(model, data, stance);
  const FootDown down = put_foot_down(model, data, q_end, foot, R_L_sole, max_corner_miss_m);
  if (!down.reached)
    return format("on one foot: the legs cannot put the %s foot down flat (a sole corner stays %.1f mm off)", name, 1e3 * down.corner_miss_m);
  update_kinematics(model, data, down.q);
  const Iso3 X_down = sole_frame_W(model, data, foot, R_L_sole[fi]);
  const double fps = motion.fps;
  const int n = static_cast<int>(std::ceil(std::max(kTransitionMin_s, std::sqrt(6 * std::abs(down.root_drop_m) / kRootAccel_mps2)) * fps - 1e-9));
  if (2 * n > frames) return format("on one foot: putting the %s foot down would take %d of the lead's %d frames", name, n, frames);
  const int guard = static_cast<int>(std::ceil(kGuard_s * fps - 1e-9));
  // The clip's own touchdown after its first frame (lead-in), or lift-off before its last (lead-out).
  int clip_edge = end;
  if (at_end)
    while (clip_edge > 0 && !contact[fi][static_cast<std::size_t>(clip_edge - 1)]) --clip_edge;
  else
    while (clip_edge < T && !contact[fi][static_cast<std::size_t>(clip_edge)]) ++clip_edge;

  const MatX before = motion.q;
  const std::vector<std::uint8_t> contact_before = contact[fi];
  const Sole& sole = model.soles()[fi];
  const VecX step = difference(model, q_end, down.q, 1.0);
  const LandmarkIk ik(model, sole_ik_options(true));
  std::vector<IkTarget> targets(2);
  targets[si] = sole_pose_target(model, stance, X_stance, R_L_sole[si]);
  const Quat R_down(X_down.linear()), R_up(X_up.linear());
  // Lead-in: down on frames [0, frames - n), lifting on [frames - n, frames); lead-out: lowering on
  // [T - frames, T - frames + n), down after.
  const int first = at_end ? T - frames : 0;
  bool held = true;
  for (int k = first; k < first + frames; ++k) {
    const int into = at_end ? k - first + 1 : frames - k;  // frames from the clip's end frame
    const bool down_here = into > n;
    contact[fi][static_cast<std::size_t>(k)] = down_here;
    if (down_here) {
      motion.q.col(k) = down.q;
      continue;
    }
    const double s = smoothstep(static_cast<double>(into) / (n + 1));  // 0 at the end pose, 1 down
    const VecX q_blend = integrate(model, q_end, step, s);
    Iso3 X = Iso3::Identity();
    X.translation() = (1 - s) * X_up.translation() + s * X_down.translation();
    X.linear() = R_up.slerp(s, R_down).toRotationMatrix();
    // Frames of the swing (which runs on into the clip) from its lift-off and to its touchdown.
    const int swing_distance = at_end ? std::min(k - clip_edge + 1, first + n - k) : std::min(k - (frames - n) + 1, clip_edge - k);
    const double min_corner = floor_z + (kClearance_m + kSlack_m) * std::min(1.0, static_cast<double>(swing_distance) / (guard + 1));
    X.translation().z() += std::max(0.0, min_corner - lowest_corner_z(X, sole));
    targets[fi] = sole_pose_target(model, foot, X, R_L_sole[fi]);
    VecX q = q_blend;
    ik.solve(data, targets, q_blend, q);
    motion.q.col(k) = q;
    // Held: the stance sole's corners and the moving sole's within the miss of their targets.
    update_kinematics(model, data, q);
    held = held && sole_corner_miss(model, data, stance, R_L_sole[si], X_stance) <= max_corner_miss_m &&
           sole_corner_miss(model, data, foot, R_L_sole[fi], X) <= max_corner_miss_m;
  }
  if (!held) {
    motion.q = before;
    contact[fi] = contact_before;
    return format("on one foot: the legs cannot carry the %s foot between the floor and its pose within %.1f mm", name,
                  1e3 * max_corner_miss_m);
  }
  return format("on both feet: the %s foot put down%s", name,
                down.root_drop_m > 1e-4 ? format(", the root lowered %.0f mm for it", 1e3 * down.root_drop_m).c_str() : "");
}

}  // namespace

void ComPlanPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  if (clip.motion.num_frames() == 0) throw InputError("--passes", "com-plan needs the robot motion of the ik pass: put ik before com-plan");
  if (!(options_.export_fps >= 1 && options_.export_fps <= 1000)) throw InputError("com-plan{fps}", "must be in [1, 1000] Hz");
  // Wall time per stage [ms], all rounds (the -v statistics).
  double ms_setup = 0, ms_plan = 0, ms_follow = 0, ms_zmp = 0, ms_whole_body = 0;
  LapTimer timer;
  // The pass works on the export grid (see the header): the clip's per-frame arrays resampled to
  // it, and moved into the clip only if the pass keeps its result.
  Clip work = resample_clip_frames(clip, options_.export_fps);
  RobotMotion& motion = work.motion;
  if (!(options_.lead_s >= 0 && options_.lead_s <= 5)) throw InputError("com-plan{lead}", "must be in [0, 5] s");
  if (!(options_.lead_speed_mps >= 0)) throw InputError("com-plan{lead_speed}", "must be >= 0 m/s");

  // A clip that starts (ends) moving cannot be planned at rest on its first (last) frame without
  // bending its first (last) step: a standing lead-in (lead-out) holding that end's pose and
  // contacts is added, in which the plan starts (stops) the COM (to the work copy: a pass that
  // keeps nothing leaves the clip without it).
  std::array<double, 2> end_speed{{0, 0}};
  std::array<int, 2> lead{{0, 0}};
  for (int e = 0; e < 2; ++e) {
    end_speed[static_cast<std::size_t>(e)] = end_com_speed(model, data, motion, e == 1);
    const bool rest = e == 0 ? options_.plan.rest_at_start : options_.plan.rest_at_end;
    // No lead where that end is airborne: there is nothing to stand on.
    const std::size_t end = e == 0 ? 0 : static_cast<std::size_t>(motion.num_frames() - 1);
    const bool standing = work.contacts.empty() || work.contacts.in_contact[0][end] || work.contacts.in_contact[1][end];
    if (rest && standing && options_.lead_s > 0 && end_speed[static_cast<std::size_t>(e)] > options_.lead_speed_mps)
      lead[static_cast<std::size_t>(e)] = static_cast<int>(std::lround(options_.lead_s * motion.fps));
  }
  hold_clip_ends(work, lead[0], lead[1]);
  std::array<std::string, 2> lead_stance;
  for (int e = 0; e < 2; ++e)
    if (lead[static_cast<std::size_t>(e)] > 0)
      lead_stance[static_cast<std::size_t>(e)] =
          stand_lead_on_both_feet(model, data, work, lead[static_cast<std::size_t>(e)], e == 1, options_.foot_tolerance_m);

  const int T = motion.num_frames();
  if (!(options_.plan.period_s > 0 && options_.plan.period_s <= 0.1)) throw InputError("com-plan{period}", "must be in (0, 0.1] s");
  // The plan is linearly interpolated to the frames: a grid coarser than them would put kinks
  // between its samples into the frames' second differences (the ZMP).
  const double fps = motion.fps, dt = std::min(options_.plan.period_s, 1 / fps);
  if (!(options_.margin_m >= 0 && options_.margin_m < 0.1)) throw InputError("com-plan{margin}", "must be in [0, 0.1) m");
  if (options_.iterations < 0 || options_.iterations > 20) throw InputError("com-plan{iterations}", "must be 0 to 20");
  if (options_.ik_iterations < 1 || options_.ik_iterations > 1000) throw InputError("com-plan{ik_iterations}", "must be 1 to 1000");
  if (!(options_.smoothing_s >= 0 && options_.smoothing_s <= 0.5)) throw InputError("com-plan{smoothing}", "must be in [0, 0.5] s");
  if (!(options_.swing_smoothing_s >= 0 && options_.swing_smoothing_s <= 0.5))
    throw InputError("com-plan{swing_smoothing}", "must be in [0, 0.5] s");
  if (!(options_.max_offset_m >= 0 && options_.max_offset_m <= 1)) throw InputError("com-plan{max_offset}", "must be in [0, 1] m");
  if (!(options_.foot_tolerance_m > 0 && options_.follow_tolerance_m > 0))
    throw InputError("com-plan{foot_tolerance, follow_tolerance}", "must be > 0 m");
  for (const auto& [name, value] : {std::pair<const char*, double>{"com_weight", options_.com_weight},
                                    {"foot_weight", options_.foot_weight},
                                    {"com_tracking", options_.plan.com_weight}})
    if (!(value > 0 && value < 1e12)) throw InputError(std::string("com-plan{") + name + "}", "must be in (0, 1e12)");
  for (const auto& [name, value] : {std::pair<const char*, double>{"jerk", options_.plan.jerk_weight},
                                    {"flight_acceleration", options_.plan.flight_acceleration_weight},
                                    {"landmark_factor", options_.landmark_factor},
                                    {"posture_regularization", options_.posture_regularization}})
    if (!(value >= 0 && value < 1e12)) throw InputError(std::string("com-plan{") + name + "}", "must be in [0, 1e12)");
  if (!(options_.velocity_margin < 1)) throw InputError("com-plan{velocity_margin}", "must be below 1");
  const std::string where = clip.human.source.path.empty() ? clip.name : clip.human.source.path;
  const bool labelled = !work.contacts.empty();
  const MatX q_in = motion.q;

  // What the COM-following IK follows, low-passed (see the header).
  const MatX q_smooth = smooth_motion(q_in, options_.smoothing_s * fps);

  // Per frame: held sole poses and the support polygon of the stance soles. Stance soles stay
  // where they are; a swing sole follows its low-passed trajectory, bent to meet the stance poses
  // at lift-off and touchdown (the low-pass alone would jump there) and never lower than it was.
  const std::array<Mat3, 2> R_L_sole = sole_frames_in_links(model, data);
  const std::array<SoleReach, 2> reach =
      options_.ankle_reach ? ankle_reach(model, model.total_mass_kg() * kGravity) : whole_soles(model);
  Frames frames;
  frames.soles.resize(static_cast<std::size_t>(T));
  frames.polygon.resize(static_cast<std::size_t>(T));
  std::vector<std::vector<HalfPlane>> shrunk(static_cast<std::size_t>(T));
  std::array<MatX, 2> sole_pose;  // per foot: 7 x T, position and quaternion (w, x, y, z)
  for (auto& p : sole_pose) p.resize(7, T);
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q_in.col(f));
    std::array<bool, 2> down{{true, true}};
    for (std::size_t k = 0; k < 2; ++k) {
      if (labelled) down[k] = work.contacts.in_contact[k][static_cast<std::size_t>(f)] != 0;
      const Sole& sole = model.soles()[k];
      const Iso3 X = link_pose(model, data, sole.link);
      const Quat R(X.linear() * R_L_sole[k]);
      sole_pose[k].col(f) << X * sole.p_L_center, R.w(), R.x(), R.y(), R.z();
      if (f > 0 && sole_pose[k].col(f).tail<4>().dot(sole_pose[k].col(f - 1).tail<4>()) < 0) sole_pose[k].col(f).tail<4>() *= -1;
    }
    frames.polygon[static_cast<std::size_t>(f)] = stance_support_polygon(model, data, down);
    shrunk[static_cast<std::size_t>(f)] = stance_support_polygon(model, data, down, reach).half_planes(options_.margin_m);
  }
  for (std::size_t k = 0; k < 2; ++k) {
    MatX held = sole_pose[k];
    if (labelled && options_.swing_smoothing_s > 0) {
      const MatX low = gaussian_filter(sole_pose[k], options_.swing_smoothing_s * fps);
      const auto& c = work.contacts.in_contact[k];
      for (int a = 0; a < T;) {
        if (c[static_cast<std::size_t>(a)]) {
          ++a;
          continue;
        }
        int b = a;
        while (b + 1 < T && !c[static_cast<std::size_t>(b + 1)]) ++b;
        // Swing a..b: the low-passed poses minus the mismatch at the stance frames around it,
        // blended linearly across the swing.
        const VecX d_a = a > 0 ? VecX(low.col(a - 1) - held.col(a - 1)) : VecX::Zero(7);
        const VecX d_b = b + 1 < T ? VecX(low.col(b + 1) - held.col(b + 1)) : VecX::Zero(7);
        for (int f = a; f <= b; ++f) {
          const double w = static_cast<double>(f - a + 1) / (b - a + 2);
          held.col(f) = low.col(f) - (1 - w) * d_a - w * d_b;
          // Never lower than the sole was: the low-pass rounds the swing's peak and its ends, where
          // refine kept the floor clearance.
          held(2, f) += std::max(0.0, raise_to_clear(held.col(f), sole_pose[k].col(f), model.soles()[k]));
        }
        // ... and the kinks of that max rounded off again (a third of the low-pass, within the swing,
        // whose ends are the stance heights), which can dip below the bound where it bent, so the
        // bound is applied once more.
        if (a > 0 && b + 1 < T) {
          const MatX z = gaussian_filter(held.block(2, a - 1, 1, b - a + 3), options_.swing_smoothing_s * fps / 3);
          held.block(2, a, 1, b - a + 1) = z.middleCols(1, b - a + 1);
          for (int f = a; f <= b; ++f)
            held(2, f) += std::max(0.0, raise_to_clear(held.col(f), sole_pose[k].col(f), model.soles()[k]));
        }
        a = b + 1;
      }
    }
    for (int f = 0; f < T; ++f) {
      const Sole& sole = model.soles()[k];
      IkTarget& t = frames.soles[static_cast<std::size_t>(f)][k];
      t.link = sole.link;
      t.p_L = sole.p_L_center;
      t.p_W = held.col(f).head<3>();
      t.weight = options_.foot_weight;
      t.R_L_frame = R_L_sole[k];
      t.R_W = Quat(held(3, f), held(4, f), held(5, f), held(6, f)).normalized();
      t.orientation_weight = options_.foot_weight;
    }
  }

  // The low-passed motion's multibody ZMP: its COM, the COM height to hold (low-passed once more),
  // the cart-table gain of that height, and the angular-momentum part of the ZMP.
  const double sigma = options_.smoothing_s * fps;
  const MultibodyZmp original = multibody_zmp(model, data, q_in, fps);
  const MultibodyZmp smooth = multibody_zmp(model, data, q_smooth, fps);
  const Eigen::Matrix2Xd com_in = smooth.com_W.topRows<2>();
  const VecX com_z = gaussian_filter(smooth.com_W.row(2), sigma).row(0).transpose();
  VecX gain(T);
  for (int f = 0; f < T; ++f) {
    const int i = std::clamp(f, 1, std::max(T - 2, 1));
    const double acc = T >= 3 ? (com_z[i + 1] - 2 * com_z[i] + com_z[i - 1]) * fps * fps : 0.0;
    gain[f] = com_z[f] / std::max(kGravity + acc, 0.1 * kGravity);
  }
  // Clipped to max_offset: a longer one comes from a glitch of the retargeted motion (a frame whose
  // limbs flip) or asks for more than any COM motion can give; the ZMP metric still reports it.
  int clipped_offsets = 0;
  auto angular_part = [&](const MultibodyZmp& z, const Eigen::Matrix2Xd& com_xy) -> Eigen::Matrix2Xd {
    Eigen::Matrix2Xd d = gaussian_filter(z.zmp_W - cart_table_zmp(com_xy, gain, fps), sigma);
    for (int f = 0; f < T; ++f) {
      const double len = d.col(f).norm();
      if (len > options_.max_offset_m) {
        d.col(f) *= options_.max_offset_m / len;
        ++clipped_offsets;
      }
    }
    return d;
  };
  Eigen::Matrix2Xd offset = angular_part(smooth, com_in);
  auto raw_angular_median = [&](const MultibodyZmp& z) {
    const Eigen::Matrix2Xd part = z.zmp_W - cart_table_zmp(z.com_W.topRows<2>(), z.zmp_gain_s2, fps);
    std::vector<double> len;
    for (int f = 0; f < T; ++f) len.push_back(part.col(f).norm());
    std::nth_element(len.begin(), len.begin() + T / 2, len.end());
    return len[static_cast<std::size_t>(T / 2)];
  };
  ctx.statistics.set("angular-part-input", raw_angular_median(original), "m", format("median; low-passed input %.3f m", raw_angular_median(smooth)));
  {
    std::vector<double> m;
    for (int f = 0; f < T; ++f) m.push_back(offset.col(f).norm());
    std::sort(m.begin(), m.end());
    ctx.statistics.set("angular-zmp-offset", m[m.size() / 2], "m", format("median; p95 %.3f, max %.3f m (first round)", m[m.size() * 95 / 100], m.back()));
  }

  // Planning grid.
  const int K = static_cast<int>(std::floor((T - 1) / fps / dt + 1e-9)) + 1;
  std::vector<ZmpPlanSample> samples(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) {
    ZmpPlanSample& s = samples[static_cast<std::size_t>(k)];
    const double t = k * dt;
    s.com_ref_W = at_time(com_in, fps, t);
    s.zmp_gain_s2 = at_time(gain.transpose(), fps, t)[0];
    s.zmp_offset_W = at_time(offset, fps, t);
    s.support = shrunk[static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(t * fps)), 0, T - 1))];
  }
  ZmpPlanOptions plan_options = options_.plan;
  plan_options.period_s = dt;
  // A body at rest has no momentum to change: its ZMP is its COM. The plan's rested ends (three
  // samples held equal) get no multibody offset, so the clip starts and ends on a COM its support
  // holds statically (with the moving motion's offset, G1's PyMO walk started with its COM 2 cm
  // beyond the stance toe, a pose no robot can be put in at rest).
  auto zero_rest_offsets = [&] {
    if (K < 7) return;
    for (int k = 0; k < 3; ++k) {
      if (plan_options.rest_at_start) samples[static_cast<std::size_t>(k)].zmp_offset_W.setZero();
      if (plan_options.rest_at_end) samples[static_cast<std::size_t>(K - 1 - k)].zmp_offset_W.setZero();
    }
  };
  zero_rest_offsets();

  // COM-following IK.
  IkOptions ik_options;
  ik_options.max_iterations = options_.ik_iterations;
  ik_options.regularization = options_.posture_regularization;
  ik_options.step_tolerance = 1e-9;  // micrometres: see the header
  ik_options.cost_tolerance = 1e-10;
  // Levenberg–Marquardt's first damping is relative to the mean diagonal, which the held soles
  // (foot_weight) dominate: the default 1e-3 starts about 1e5 times the posture's curvature and the
  // solve spent its iterations lowering it (18 per frame, against 9 from here, at the same result).
  ik_options.initial_damping = 1e-9;
  const LandmarkIk ik(model, ik_options);
  // The first frame starts cold (later frames start from their predecessor's correction): with
  // the same iterations it stopped about 3 mm short of its COM height, a jump into the next frame.
  IkOptions first_ik_options = ik_options;
  first_ik_options.max_iterations = 10 * options_.ik_iterations;
  const LandmarkIk first_ik(model, first_ik_options);
  const bool have_landmarks = work.targets[Landmark::Pelvis].present && work.targets[Landmark::Pelvis].p_W.cols() == T;
  const VecX& v_max = model.velocity_limits();
  // Each frame starts from the low-passed pose plus the previous frame's correction; frames marked in
  // `kept_as_input` (empty: none) keep their input pose (see ComPlanPassOptions::repairs).
  auto follow = [&](const Eigen::Matrix2Xd& com_target, const std::vector<std::uint8_t>& kept_as_input, bool repairing) {
    Follow out;
    out.q = q_in;
    out.foot_error_m.assign(static_cast<std::size_t>(T), 0.0);
    out.kept_as_input = kept_as_input;
    VecX correction = VecX::Zero(model.nv());
    IkJointBounds bounds;
    bounds.lower.resize(model.nu());
    bounds.upper.resize(model.nu());
    std::vector<IkTarget> targets;
    // Frames to the nearest kept frame: the `ramp` frames either side of a kept passage follow a
    // pose and a COM blended (a raised cosine) from the low-passed ones towards the input's, so the
    // motion joins the kept frames without a jump, its soles held by the IK.
    const int ramp = std::max(2, static_cast<int>(std::lround(0.1 * fps)));
    std::vector<int> to_kept(static_cast<std::size_t>(T), std::numeric_limits<int>::max()), until_kept = to_kept;
    if (!kept_as_input.empty()) {
      for (int f = T - 1, next = -1; f >= 0; --f) {
        if (kept_as_input[static_cast<std::size_t>(f)]) next = f;
        if (next >= 0) until_kept[static_cast<std::size_t>(f)] = next - f;
      }
      for (int f = 0, last = -1; f < T; ++f) {
        if (kept_as_input[static_cast<std::size_t>(f)]) last = f;
        to_kept[static_cast<std::size_t>(f)] = std::min(until_kept[static_cast<std::size_t>(f)], last >= 0 ? f - last : std::numeric_limits<int>::max());
      }
    }
    for (int f = 0; f < T; ++f) {
      const int d = to_kept[static_cast<std::size_t>(f)];
      if (d == 0) {  // out.q is q_in there
        correction = difference(model, q_smooth.col(f), q_in.col(f), 1.0);
        continue;
      }
      const double u = d <= ramp ? 0.5 * (1 + std::cos(M_PI * d / (ramp + 1))) : 0.0;
      const VecX q_frame = u > 0 ? integrate(model, q_smooth.col(f), difference(model, q_smooth.col(f), q_in.col(f), 1.0), u)
                                 : VecX(q_smooth.col(f));
      targets.assign(frames.soles[static_cast<std::size_t>(f)].begin(), frames.soles[static_cast<std::size_t>(f)].end());
      if (have_landmarks)
        for (IkTarget t : make_ik_targets(model, ik, work.targets, f, 0.5)) {
          if (on_a_foot(model, t.link)) continue;
          t.weight *= options_.landmark_factor;
          t.orientation_weight *= options_.landmark_factor;
          targets.push_back(t);
        }
      IkComTarget com;
      com.p_W << com_target.col(f), com_z[f];
      if (u > 0) com.p_W = (1 - u) * com.p_W + u * original.com_W.col(f);
      com.weight = options_.com_weight;
      com.horizontal_only = false;
      const IkJointBounds* b = nullptr;
      const int ahead = until_kept[static_cast<std::size_t>(f)];  // frames to the next kept one
      if (f > 0 || ahead <= ramp) {
        for (int i = 0; i < model.nu(); ++i) {
          const double limit_step = v_max[i] > 0 ? (1 - options_.velocity_margin) * v_max[i] / fps : INFINITY;
          double lo = -INFINITY, hi = INFINITY;
          if (f > 0) {
            const double step = std::max(limit_step, std::abs(q_in(7 + i, f) - q_in(7 + i, f - 1)));
            lo = out.q(7 + i, f - 1) - step;
            hi = out.q(7 + i, f - 1) + step;
          }
          // ... and within reach of the next kept frame at the speed limits (where both cannot
          // hold, half way between them).
          if (ahead <= ramp) {
            const double target = q_in(7 + i, f + ahead);
            const double lo_k = target - ahead * limit_step, hi_k = target + ahead * limit_step;
            const double lo2 = std::max(lo, lo_k), hi2 = std::min(hi, hi_k);
            if (lo2 <= hi2) {
              lo = lo2;
              hi = hi2;
            } else {
              lo = hi = 0.5 * (lo2 + hi2);
            }
          }
          bounds.lower[i] = lo;
          bounds.upper[i] = hi;
        }
        b = &bounds;
      }
      VecX q = integrate(model, q_frame, correction, 1.0);
      // In a repair, the floor as firm as the soles (stance soles, held by their targets, left out):
      // a pinned COM or a frame joining a kept one must not be bought by a hand or a knee through
      // the floor. (Elsewhere the whole-body stage's floor rows hold it, as they always did.)
      IkFloorTerm floor;
      if (repairing) floor.weight = options_.foot_weight;
      for (std::size_t foot = 0; foot < 2; ++foot)
        if (!labelled || work.contacts.in_contact[foot][static_cast<std::size_t>(f)]) floor.skip_links[foot] = model.soles()[foot].link;
      (f == 0 ? first_ik : ik).solve(data, targets, q_frame, q, com, floor, b);
      update_kinematics(model, data, q);
      const double miss = (com_position(model, data) - com.p_W).norm();
      if (miss > options_.follow_tolerance_m) ++out.missed_frames;
      if (miss > out.max_miss_m) {
        out.max_miss_m = miss;
        out.max_miss_time_s = f / fps;
      }
      for (const IkTarget& s : frames.soles[static_cast<std::size_t>(f)])
        out.foot_error_m[static_cast<std::size_t>(f)] = std::max(out.foot_error_m[static_cast<std::size_t>(f)], (link_point(model, data, s.link, s.p_L) - s.p_W).norm());
      out.max_foot_error_m = std::max(out.max_foot_error_m, out.foot_error_m[static_cast<std::size_t>(f)]);
      correction = difference(model, q_frame, q, 1.0);
      out.q.col(f) = q;
    }
    return out;
  };

  auto score = [&](const MultibodyZmp& zmp) { return score_zmp(frames.polygon, zmp, 0.0); };
  const Score before = score(original);

  Score best = before;
  Follow best_follow;
  best_follow.q = q_in;
  Eigen::Matrix2Xd best_com = com_in, best_zmp = original.zmp_W;
  MultibodyZmp best_realised = original;  // the kept motion's multibody ZMP
  double best_shift = 0;
  int rounds = 0, qp_iterations = 0;
  std::string qp_trouble, round_outside;
  int rounds_dropping_soles = 0, stages_dropping_landmarks = 0;
  // Landmark error median over the clip's own frames (the lead has no source sample), the
  // summary's metric: a result may move it by at most max_landmark_growth (the motion must stay
  // the motion; a plan that cannot be followed closer is reported, not exported).
  auto landmark_median = [&](const MatX& q) {
    if (!have_landmarks) return 0.0;
    std::vector<double> e;
    for (int f = lead[0]; f < T - lead[1]; ++f) {
      const double d = frame_landmark_error_m(model, data, work.targets, q.col(f), f);
      if (std::isfinite(d)) e.push_back(d);
    }
    if (e.empty()) return 0.0;
    std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
    return e[e.size() / 2];
  };
  const double landmarks_before = landmark_median(q_in);
  auto landmarks_held = [&](const MatX& q) {
    const bool held = landmark_median(q) <= landmarks_before + options_.max_landmark_growth_m;
    stages_dropping_landmarks += !held;
    return held;
  };
  // Issue 13's stance drift (the summary's metric: a stance sole centre's or heel's travel from where
  // its phase began): a result may not take it beyond foot_tolerance, or beyond the input's where
  // that already was. Holding each frame within foot_tolerance of the input is not enough: the
  // input's own drift and the result's can add up.
  auto stance_drift = [&](const MatX& q) {
    const QualityMetrics m =
        foot_metrics(model, data, q, fps, labelled ? work.contacts.in_contact : std::array<std::vector<std::uint8_t>, 2>{}, true);
    return std::max(m.foot_skating_max_m, m.heel_skating_max_m);
  };
  const double drift_bound = std::max(options_.foot_tolerance_m, stance_drift(q_in));
  int results_dropping_drift = 0;
  auto drift_held = [&](const MatX& q) {
    const bool held = stance_drift(q) <= drift_bound;
    results_dropping_drift += !held;
    return held;
  };
  // Per foot and frame, the height of the sole's lowest corner where it swings (+inf in stance).
  auto lowest_swing_corners = [&](const MatX& q) {
    std::array<std::vector<double>, 2> z;
    for (auto& v : z) v.assign(static_cast<std::size_t>(T), std::numeric_limits<double>::infinity());
    if (!labelled) return z;
    for (int f = 0; f < T; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      if (work.contacts.in_contact[0][fi] && work.contacts.in_contact[1][fi]) continue;
      update_kinematics(model, data, q.col(f));
      for (std::size_t foot = 0; foot < 2; ++foot) {
        if (work.contacts.in_contact[foot][fi]) continue;
        z[foot][fi] = lowest_corner_z(sole_frame_W(model, data, static_cast<int>(foot), R_L_sole[foot]), model.soles()[foot]);
      }
    }
    return z;
  };
  double max_plan_violation = 0;
  timer.lap(ms_setup);
  // Per frame, how low a result may take the robot's lowest point: issue 13's floor tolerance (2 mm)
  // or, where the input already was lower, foot_tolerance below that.
  std::vector<double> floor_at = lowest_points(model, data, q_in);
  for (double& z : floor_at) z = std::min(-kFloorTolerance_m, z - options_.foot_tolerance_m);
  // Per frame, what gave in a followed motion: bit 0, a held sole moved beyond foot_tolerance or
  // (in a repair) the body went below floor_at; bit 1 (2), the left (right) stance sole's drift went
  // beyond drift_bound.
  auto soles_gave = [&](const Follow& followed, bool repairing) {
    std::vector<std::uint8_t> gave(static_cast<std::size_t>(T), 0);
    const std::vector<double> low = repairing ? lowest_points(model, data, followed.q) : std::vector<double>(static_cast<std::size_t>(T), 0.0);
    for (int f = 0; f < T; ++f) {
      const auto fi = static_cast<std::size_t>(f);
      gave[fi] = followed.foot_error_m[fi] > options_.foot_tolerance_m || low[fi] < floor_at[fi];
    }
    if (!labelled) return gave;
    const auto travel = stance_travel(model, data, followed.q, work.contacts.in_contact, R_L_sole);
    for (std::size_t foot = 0; foot < 2; ++foot)
      for (std::size_t f = 0; f < static_cast<std::size_t>(T); ++f)
        if (travel[foot][f] > drift_bound) gave[f] |= static_cast<std::uint8_t>(2 << foot);
    return gave;
  };
  auto any_of = [](const std::vector<std::uint8_t>& v) { return std::any_of(v.begin(), v.end(), [](std::uint8_t x) { return x != 0; }); };
  // A plan on `s`, followed with the frames marked in `kept` left as they came; false where the QP failed.
  struct Candidate {
    ZmpPlan plan;
    Eigen::Matrix2Xd com_target, zmp_plan;
    Follow follow;
  };
  auto plan_and_follow = [&](const std::vector<ZmpPlanSample>& s, const std::vector<std::uint8_t>& kept, bool repairing, int round,
                             Candidate& c) {
    c.plan = plan_com_zmp(s, plan_options);
    timer.lap(ms_plan);
    qp_iterations += c.plan.solver.iterations;
    if (c.plan.solver.status != SparseQpStatus::Solved && qp_trouble.empty())
      qp_trouble = format("round %d: %s after %d iterations", round + 1, sparse_qp_status_name(c.plan.solver.status),
                          c.plan.solver.iterations);
    if (c.plan.solver.status == SparseQpStatus::Failed) return false;
    max_plan_violation = std::max(max_plan_violation, c.plan.max_violation_m);
    c.com_target.resize(2, T);
    c.zmp_plan.resize(2, T);
    for (int f = 0; f < T; ++f) {
      c.com_target.col(f) = at_time(c.plan.com_W, 1 / dt, f / fps);
      c.zmp_plan.col(f) = at_time(c.plan.zmp_W, 1 / dt, f / fps);
    }
    c.follow = follow(c.com_target, kept, repairing);
    timer.lap(ms_follow);
    return true;
  };
  // Repair (ComPlanPassOptions::repairs) of a round whose followed motion gave: on a copy of the
  // samples, those within pin_window of each frame that gave are pinned to the retargeted COM and
  // the plan is solved and followed again; then, up to `repairs` times, the frames that still give
  // keep their input pose, with kKeptMargin frames either side (the legs cannot hold the soles
  // there, e.g. where the input has a glitch that the low-pass smooths), and a kept frame whose
  // stance still drifts (measured from a followed touchdown) keeps that whole stance, and the same
  // plan is followed again. True with `out` where nothing gives any more.
  int repaired_rounds = 0, repair_follows = 0, pinned_samples = 0, kept_frames = 0, rough_repairs = 0;
  const double jitter_in = joint_jitter(q_in, fps);
  auto repair = [&](const Candidate& first, int round, Candidate& out) {
    std::vector<ZmpPlanSample> s = samples;
    std::vector<std::uint8_t> kept(static_cast<std::size_t>(T), 0);
    std::vector<std::uint8_t> gave = soles_gave(first.follow, false);
    const int reach = static_cast<int>(std::floor(options_.pin_window_s / dt + 1e-9));
    int pinned = 0;
    for (int f = 0; f < T; ++f) {
      if (!gave[static_cast<std::size_t>(f)]) continue;
      const int centre = std::min(K - 1, static_cast<int>(std::lround(f / fps / dt)));
      for (int k = std::max(0, centre - reach); k <= std::min(K - 1, centre + reach); ++k) {
        pinned += s[static_cast<std::size_t>(k)].com_weight_scale != kPinnedComWeightScale;
        s[static_cast<std::size_t>(k)].com_weight_scale = kPinnedComWeightScale;
      }
    }
    ++repair_follows;
    if (!plan_and_follow(s, kept, true, round, out)) return false;
    gave = soles_gave(out.follow, true);
    for (int r = 0; r < options_.repairs && any_of(gave); ++r) {
      auto keep = [&](int a, int b) {
        for (int g = std::max(0, a); g <= std::min(T - 1, b); ++g) kept[static_cast<std::size_t>(g)] = 1;
      };
      for (int f = 0; f < T; ++f) {
        const std::uint8_t what = gave[static_cast<std::size_t>(f)];
        if (!what) continue;
        if (!kept[static_cast<std::size_t>(f)]) {
          keep(f - kKeptMargin, f + kKeptMargin);
          continue;
        }
        for (std::size_t foot = 0; foot < 2; ++foot) {
          if (!(what & (2 << foot))) continue;
          const auto& c = work.contacts.in_contact[foot];
          int a = f, b = f;
          while (a > 0 && c[static_cast<std::size_t>(a - 1)]) --a;
          while (b + 1 < T && c[static_cast<std::size_t>(b + 1)]) ++b;
          keep(a - kKeptMargin, b + kKeptMargin);
        }
      }
      ++repair_follows;
      out.follow = follow(out.com_target, kept, true);
      timer.lap(ms_follow);
      gave = soles_gave(out.follow, true);
    }
    if (any_of(gave)) return false;
    // The kept frames are joined by short ramps: a repair may not make the motion rougher than it
    // came (issue 13's jitter bar is the per-frame IK's).
    if (joint_jitter(out.follow.q, fps) > jitter_in) {
      ++rough_repairs;
      return false;
    }
    ++repaired_rounds;
    pinned_samples += pinned;
    kept_frames += static_cast<int>(std::count(kept.begin(), kept.end(), 1));
    return true;
  };
  // A round's result is kept if it improves the ZMP and holds the landmarks and the stance drift;
  // the retargeted motion itself is the first candidate.
  auto consider = [&](Candidate& c, const MultibodyZmp& realised, const Score& now) {
    if (!(now.better_than(best) && landmarks_held(c.follow.q) && drift_held(c.follow.q))) return;
    best = now;
    best_follow = std::move(c.follow);
    best_realised = realised;
    best_com = c.com_target;
    best_zmp = c.zmp_plan;
    best_shift = c.plan.max_shift_m;
  };
  for (int round = 0; round < options_.iterations; ++round) {
    Candidate c;
    if (!plan_and_follow(samples, {}, false, round, c)) break;
    ++rounds;
    const MultibodyZmp realised = multibody_zmp(model, data, c.follow.q, fps);
    const Score now = score(realised);
    round_outside += format("%s%d (angular part median %.3f m)", round ? ", " : "", now.outside, raw_angular_median(realised));
    // The round must hold the soles (stance fixed, swing on its path, the stance drift); where it
    // does not, its repair is the candidate.
    if (!any_of(soles_gave(c.follow, false))) {
      consider(c, realised, now);
    } else {
      if (c.follow.max_foot_error_m > options_.foot_tolerance_m) ++rounds_dropping_soles; else ++results_dropping_drift;
      Candidate r;
      if (options_.repairs > 0 && repair(c, round, r)) {
        const MultibodyZmp realised_r = multibody_zmp(model, data, r.follow.q, fps);
        const Score now_r = score(realised_r);
        round_outside += format(", repaired %d", now_r.outside);
        consider(r, realised_r, now_r);
      }
    }
    if (now.outside == 0) break;
    // Two-stage preview: the next plan's offset is what the multibody motion (unrepaired: the
    // rounds converge as without repairs) adds to this plan's cart-table ZMP.
    offset = angular_part(realised, c.com_target);
    for (int k = 0; k < K; ++k) samples[static_cast<std::size_t>(k)].zmp_offset_W = at_time(offset, fps, k * dt);
    zero_rest_offsets();
    timer.lap(ms_zmp);
  }
  const std::vector<std::uint8_t> kept_as_input =
      best_follow.kept_as_input.empty() ? std::vector<std::uint8_t>(static_cast<std::size_t>(T), 0) : best_follow.kept_as_input;

  // 5. Whole-body stage: what the COM plan leaves outside (mostly the angular-momentum part the
  // rounds cannot predict) removed by the smallest smooth joint-space correction whose multibody
  // ZMP rows hold the ZMP in the support shrunk by the margin, the soles where they are (stance
  // held, swing on its path), the floor, the limits and the speed limits (refine's smooth correction
  // with ZMP rows); frames where it still breaks a sole take its start back; kept if the ZMP improves
  // and the soles stay held.
  struct Stage {
    bool kept = false;
    MatX q;
    MultibodyZmp z;
    Score after;         // stance frames more than 1 cm outside
    std::string detail;  // the -v statistic's
  };
  auto whole_body_stage = [&](const MatX& q0, const std::vector<std::uint8_t>& kept_as_input, const MultibodyZmp& realised0) {
    refine::CorrectionReport whole_body;
    refine::FootPlan feet;
    refine::CorrectionOptions co;
    co.zmp_support = shrunk;
    // No ZMP rows where the rounds left the input's poses (its stencil reaches a frame either side):
    // the legs could not hold the soles there even on the retargeted COM.
    for (int f = 0; f < T; ++f)
      if (kept_as_input[static_cast<std::size_t>(f)])
        for (int g = std::max(0, f - 1); g <= std::min(T - 1, f + 1); ++g) co.zmp_support[static_cast<std::size_t>(g)].clear();
    for (std::size_t k = 0; k < 2; ++k) feet.feet[k].resize(static_cast<std::size_t>(T));
    for (int f = 0; f < T; ++f) {
      update_kinematics(model, data, q0.col(f));
      for (std::size_t foot = 0; foot < 2; ++foot) {
        const bool down = !labelled || work.contacts.in_contact[foot][static_cast<std::size_t>(f)] != 0;
        const Iso3 X = link_pose(model, data, model.soles()[foot].link);
        refine::FootTarget& t = feet.feet[foot][static_cast<std::size_t>(f)];
        t.mode = down ? refine::FootMode::Stance : refine::FootMode::Swing;
        t.pose.p_W = X * model.soles()[foot].p_L_center;
        t.pose.R_W = X.linear() * R_L_sole[foot];
      }
    }
    // The ZMP rows' Jacobians are large (c_z fps² / g ≈ 60 at 30 fps): the stance rows are firmer
    // than refine's so the soles win.
    co.stance_weight = 1e8;
    co.swing_weight = 1e4;
    co.q_lower = model.q_lower().array() + 1e-4;
    co.q_upper = model.q_upper().array() - 1e-4;
    co.max_step = (1 - options_.velocity_margin) * v_max / fps;
    co.lambda = refine::smoothing_lambda(options_.whole_body_smoothing_hz, fps);
    co.stiffness = refine::legs_first_stiffness(model);  // who moves: the legs first (refine's rule)
    co.R_L_sole = R_L_sole;
    co.iterations = options_.whole_body_iterations;
    co.zmp_weight = options_.whole_body_zmp_weight;
    co.fps = fps;
    co.zmp_rest_start = options_.plan.rest_at_start;
    co.zmp_rest_end = options_.plan.rest_at_end;
    MatX q1 = refine::solve_smooth_correction(model, data, q0, q0, feet, co, &whole_body);
    // Plain Gauss–Newton first; where it stops with a ZMP row beyond what the metric forgives (1 cm
    // outside the soles: the margin plus 1 cm past the shrunk polygon), again with the further steps
    // and damped retries. Where it does not, they would only polish rows already within 1 cm (on
    // G1's CMU walk: 200 ms more, no frame gained).
    if (options_.whole_body_extra_iterations > 0 && whole_body.zmp_excess_max > options_.margin_m + kZmpNear_m) {
      co.extra_iterations = options_.whole_body_extra_iterations;
      q1 = refine::solve_smooth_correction(model, data, q0, q0, feet, co, &whole_body);
    }
    // The limit, speed, stance and swing rows are penalties: joints are clamped into their limits,
    // and where a ZMP row pulled harder than a stance row (or a clamp moved a leg) the frame is
    // projected back onto its held soles by the smallest change (each joint within ±0.05 rad, so no
    // leg changes branch within a frame), a swing sole that came down too low (below
    // `swing_floor_at`) back onto its path; last, each joint's step is cut to its speed limit (a
    // joint beyond it rejoins its trajectory as fast as the limit allows; the speed rows keep
    // `velocity_margin` free, so what is left between the margin and the limit stays).
    const std::array<std::vector<double>, 2> swing_floor = lowest_swing_corners(q0);
    auto swing_floor_at = [&](std::size_t foot, std::size_t f) {
      // The swing clearance where the sole was above it, else foot_tolerance under where it was.
      const double z0 = swing_floor[foot][f];
      return z0 >= kSwingClearance_m ? kSwingClearance_m : z0 - options_.foot_tolerance_m;
    };
    for (int i = 0; i < model.nu(); ++i) q1.row(7 + i) = q1.row(7 + i).cwiseMax(model.q_lower()[i]).cwiseMin(model.q_upper()[i]);
    IkOptions hold_options;
    hold_options.max_iterations = 20;
    hold_options.regularization = 1e-6;
    hold_options.step_tolerance = 1e-10;
    hold_options.cost_tolerance = 1e-12;
    const LandmarkIk hold_ik(model, hold_options);
    // Frames whose held soles gave (or whose swing sole came down too low) projected back, on the
    // frames marked in `only` (empty: all).
    auto project_holds = [&](MatX& q1, const std::vector<double>& only) {
      std::vector<IkTarget> held;
      IkJointBounds step;
      for (int f = 0; f < T; ++f) {
        if (!only.empty() && !(only[static_cast<std::size_t>(f)] > 0)) continue;
        update_kinematics(model, data, q1.col(f));
        held.clear();
        double off = 0;
        bool swing_low = false;
        for (std::size_t foot = 0; foot < 2; ++foot) {
          const IkTarget& t = frames.soles[static_cast<std::size_t>(f)][foot];
          if (labelled && !work.contacts.in_contact[foot][static_cast<std::size_t>(f)]) {
            const Iso3 X = sole_frame_W(model, data, static_cast<int>(foot), R_L_sole[foot]);
            const double dip = swing_floor_at(foot, static_cast<std::size_t>(f)) - lowest_corner_z(X, model.soles()[foot]);
            if (dip <= 0) continue;
            IkTarget lifted = t;  // the sole as the stage left it, raised onto its floor
            lifted.p_W = X.translation() + Vec3(0, 0, dip + 1e-4);
            lifted.R_W = Quat(X.linear());
            held.push_back(lifted);
            swing_low = true;
            continue;
          }
          off = std::max(off, (link_point(model, data, t.link, t.p_L) - t.p_W).norm());
          held.push_back(t);
        }
        if (off <= 2e-4 && !swing_low) continue;
        step.lower = (q1.col(f).tail(model.nu()).array() - 0.05).cwiseMax(model.q_lower().array());
        step.upper = (q1.col(f).tail(model.nu()).array() + 0.05).cwiseMin(model.q_upper().array());
        VecX q = q1.col(f);
        hold_ik.solve(data, held, q1.col(f), q, {}, {}, &step);
        q1.col(f) = q;
      }
    };
    project_holds(q1, {});
    // (A step the stage started from is allowed: where the input already was faster than a limit, a
    // clamp would drag every later frame along. Frames given back whole, weight 1 in `given`, are
    // the stage's start itself and stay.)
    constexpr double kClampShare = 1 - 1e-6;  // a step clamped to the limit stays below it once rounded
    auto clamp_speeds = [&](MatX& q, const std::vector<double>& given) {
      for (int i = 0; i < model.nu(); ++i) {
        if (!(v_max[i] > 0)) continue;
        for (int f = 1; f < T; ++f) {
          if (!given.empty() && given[static_cast<std::size_t>(f)] >= 1) continue;
          const double step = std::max(kClampShare * v_max[i] / fps, std::abs(q0(7 + i, f) - q0(7 + i, f - 1)));
          q(7 + i, f) = std::clamp(q(7 + i, f), q(7 + i, f - 1) - step, q(7 + i, f - 1) + step);
        }
      }
    };
    clamp_speeds(q1, {});
    // How far a stance sole moved and turned from its held pose, and how much more it tilts than
    // issue 13's 0.5° (or than it did before the stage, where it already did), how far a swing
    // sole's lowest corner is below its floor; per frame, whether any of these (or a stance drift
    // beyond what is allowed) is a fault.
    constexpr double kStanceAngle_rad = 0.5 * M_PI / 180;
    // Tilt growth below this is rounding (a frame projected back onto its soles, already tilted).
    constexpr double kTiltTolerance_rad = 0.01 * M_PI / 180;
    auto stance_tilts = [&](const MatX& q) {
      std::array<std::vector<double>, 2> tilt;
      for (auto& v : tilt) v.assign(static_cast<std::size_t>(T), 0.0);
      for (int f = 0; f < T; ++f) {
        update_kinematics(model, data, q.col(f));
        for (std::size_t foot = 0; foot < 2; ++foot)
          tilt[foot][static_cast<std::size_t>(f)] = std::acos(std::clamp(
              sole_frame_W(model, data, static_cast<int>(foot), R_L_sole[foot]).linear()(2, 2), -1.0, 1.0));
      }
      return tilt;
    };
    const std::array<std::vector<double>, 2> tilt_before = stance_tilts(q0);
    const std::vector<double> low_before = lowest_points(model, data, q0);
    constexpr double kFloorRounding_m = 1e-4;
    struct StageFaults {
      double sole_move = 0, sole_turn = 0, tilt_excess = 0, swing_dip = 0;
      double below_floor = 0;  ///< [m] how far the lowest point went below floor_at (and below where it was), at worst
      std::vector<std::uint8_t> frames;
    };
    auto stage_faults = [&](const MatX& q) {
      StageFaults out;
      out.frames.assign(static_cast<std::size_t>(T), 0);
      for (int f = 0; f < T; ++f) {
        const auto fi = static_cast<std::size_t>(f);
        update_kinematics(model, data, q.col(f));
        for (std::size_t foot = 0; foot < 2; ++foot)
          if (!labelled || work.contacts.in_contact[foot][fi]) {
            const IkTarget& t = frames.soles[fi][foot];
            const double move = (link_point(model, data, t.link, t.p_L) - t.p_W).norm();
            const Mat3 R_sole = sole_frame_W(model, data, static_cast<int>(foot), R_L_sole[foot]).linear();
            const double turn = AngleAxis(Mat3(R_sole * t.R_W.toRotationMatrix().transpose())).angle();
            const double tilt = std::acos(std::clamp(R_sole(2, 2), -1.0, 1.0)) - std::max(kStanceAngle_rad, tilt_before[foot][fi]);
            out.sole_move = std::max(out.sole_move, move);
            out.sole_turn = std::max(out.sole_turn, turn);
            out.tilt_excess = std::max(out.tilt_excess, tilt);
            if (move > options_.foot_tolerance_m || turn > kStanceAngle_rad || tilt > kTiltTolerance_rad) out.frames[fi] = 1;
          }
      }
      const std::array<std::vector<double>, 2> swing_now = lowest_swing_corners(q);
      for (std::size_t foot = 0; foot < 2; ++foot)
        for (std::size_t f = 0; f < swing_now[foot].size(); ++f) {
          const double dip = swing_floor_at(foot, f) - swing_now[foot][f];
          out.swing_dip = std::max(out.swing_dip, dip);
          if (dip > 0) out.frames[f] = 1;
        }
      // Below floor_at, and lower than the stage's start (whose floor, where it was already lower,
      // the stage may only improve).
      const std::vector<double> low = lowest_points(model, data, q);
      for (std::size_t f = 0; f < static_cast<std::size_t>(T); ++f) {
        if (!(low[f] < floor_at[f] && low[f] < low_before[f] - kFloorRounding_m)) continue;
        out.below_floor = std::max(out.below_floor, floor_at[f] - low[f]);
        out.frames[f] = 1;
      }
      if (labelled) {
        const auto travel = stance_travel(model, data, q, work.contacts.in_contact, R_L_sole);
        for (std::size_t foot = 0; foot < 2; ++foot)
          for (std::size_t f = 0; f < static_cast<std::size_t>(T); ++f)
            if (travel[foot][f] > drift_bound) out.frames[f] = 1;
      }
      return out;
    };
    // Where the stage broke the soles (e.g. next to a passage the rounds left as it came), those
    // frames take the rounds' motion back, blended in over 0.1 s either side; at most kGiveBackPasses
    // times.
    StageFaults faults = stage_faults(q1);
    std::vector<std::uint8_t> given_back(static_cast<std::size_t>(T), 0);
    const int ramp = std::max(2, static_cast<int>(std::lround(0.1 * fps)));
    // Frames the rounds left as they came stay so (the stage had no ZMP rows there, but its smoothness
    // and speed rows move them).
    std::vector<std::uint8_t> give_back = faults.frames;
    for (int f = 0; f < T; ++f) give_back[static_cast<std::size_t>(f)] |= kept_as_input[static_cast<std::size_t>(f)];
    for (int pass = 0; options_.whole_body_give_back && pass < kGiveBackPasses && std::find(give_back.begin(), give_back.end(), 1) != give_back.end();
         ++pass) {
      std::vector<double> w(static_cast<std::size_t>(T), 0.0);
      for (int f = 0; f < T; ++f) {
        if (!give_back[static_cast<std::size_t>(f)]) continue;
        for (int g = std::max(0, f - kKeptMargin - ramp); g <= std::min(T - 1, f + kKeptMargin + ramp); ++g) {
          const int beyond = std::max(0, std::abs(g - f) - kKeptMargin);  // frames into the ramp
          w[static_cast<std::size_t>(g)] = std::max(w[static_cast<std::size_t>(g)], 0.5 * (1 + std::cos(M_PI * beyond / (ramp + 1))));
        }
      }
      for (int f = 0; f < T; ++f) {
        const double wf = w[static_cast<std::size_t>(f)];
        if (wf <= 0) continue;
        if (wf >= 1) given_back[static_cast<std::size_t>(f)] = 1;
        q1.col(f) = integrate(model, q1.col(f), difference(model, q1.col(f), q0.col(f), 1.0), wf);
      }
      project_holds(q1, w);  // the blend of two poses that hold the soles may not
      clamp_speeds(q1, w);
      faults = stage_faults(q1);
      give_back = faults.frames;
    }
    const int stage_spliced = static_cast<int>(std::count(given_back.begin(), given_back.end(), 1));
    const double sole_move = faults.sole_move, sole_turn = faults.sole_turn, tilt_excess = faults.tilt_excess,
                 swing_dip = faults.swing_dip;
    const MultibodyZmp z1 = multibody_zmp(model, data, q1, fps);
    const Score before_1cm = score_zmp(frames.polygon, realised0, kZmpNear_m),
                after_1cm = score_zmp(frames.polygon, z1, kZmpNear_m);
    const bool kept = sole_move <= options_.foot_tolerance_m && sole_turn <= kStanceAngle_rad && tilt_excess <= kTiltTolerance_rad && swing_dip <= 0 &&
                      faults.below_floor <= 0 &&
                      after_1cm.better_than(before_1cm) && landmarks_held(q1) && drift_held(q1);
    Stage st;
    st.kept = kept;
    st.after = after_1cm;
    st.detail = format("stance frames more than 1 cm outside after the whole-body stage, %d before (%s; %d iterations, "
                              "%d rows left, worst %.3f m; %d frames given back to the rounds' motion where it broke the soles; sole move "
                              "%.4f m, turn %.2f deg, tilt %.2f deg over, swing sole %.4f m too low)",
                              before_1cm.outside, kept ? "kept" : "dropped", whole_body.iterations, whole_body.zmp_rows,
                              whole_body.zmp_excess_max, stage_spliced, sole_move, sole_turn * 180 / M_PI,
                              std::max(0.0, tilt_excess) * 180 / M_PI, std::max(0.0, swing_dip));
    st.q = std::move(q1);
    st.z = z1;
    return st;
  };
  if (options_.whole_body_iterations > 0 && T >= 4) {
    Stage st = whole_body_stage(best_follow.q, kept_as_input, best_realised);
    // Where it cannot be kept on the rounds' result, the stage starts from the retargeted motion
    // itself, and is kept if it ends with fewer stance frames outside than that result.
    if (!st.kept && (best_follow.q - q_in).cwiseAbs().maxCoeff() != 0) {
      Stage again = whole_body_stage(q_in, std::vector<std::uint8_t>(static_cast<std::size_t>(T), 0), original);
      if (again.kept && again.after.better_than(score_zmp(frames.polygon, best_realised, kZmpNear_m))) {
        st = std::move(again);
        st.detail += " (from the retargeted motion: the rounds' result could not keep it)";
        best_follow = Follow{};
        best_shift = 0;
      }
    }
    ctx.statistics.set("whole-body-zmp", st.after.outside, "frames", st.detail);
    if (st.kept) {
      best_follow.q = std::move(st.q);
      best = score(st.z);
      best_com = st.z.com_W.topRows<2>();
      best_zmp = st.z.zmp_W;  // the exported balance reference: what the rows held
      best_realised = st.z;
    }
  }
  timer.lap(ms_whole_body);

  const bool unchanged = (best_follow.q - motion.q).cwiseAbs().maxCoeff() == 0;
  // The result's stance frames more than 1 cm outside (the metric's "within 1 cm", design.md §6).
  const Score exported = unchanged ? Score{} : score_zmp(frames.polygon, best_realised, kZmpNear_m);
  if (unchanged) {
    // Nothing kept: the clip stays as it came (its rate, no lead frames); its balance reference is
    // the retargeted COM and multibody ZMP.
    lead = {{0, 0}};
    const MultibodyZmp z = multibody_zmp(model, data, clip.motion.q, clip.motion.fps);
    clip.com_replanned_W = z.com_W;
    clip.cop_predicted_W = z.zmp_W;
  } else {
    motion.q = std::move(best_follow.q);
    clip.motion = std::move(work.motion);
    clip.contacts = std::move(work.contacts);
    clip.targets = std::move(work.targets);
    clip.lead_in_frames = work.lead_in_frames;
    clip.lead_out_frames = work.lead_out_frames;
    clip.com_replanned_W.resize(3, T);
    clip.com_replanned_W.topRows<2>() = best_com;
    clip.com_replanned_W.row(2) = com_z.transpose();
    clip.cop_predicted_W = best_zmp;
  }
  for (int e = 0; e < 2; ++e)
    ctx.statistics.set(e == 0 ? "lead-in" : "lead-out", lead[static_cast<std::size_t>(e)] / fps, "s",
                       format("standing frames added %s the clip (its COM %s at %.2f m/s; threshold %.2f m/s)%s%s",
                              e == 0 ? "before" : "after", e == 0 ? "starts" : "ends",
                              end_speed[static_cast<std::size_t>(e)], options_.lead_speed_mps,
                              lead_stance[static_cast<std::size_t>(e)].empty() ? "" : ("; " + lead_stance[static_cast<std::size_t>(e)]).c_str(),
                              unchanged && (end_speed[static_cast<std::size_t>(e)] > options_.lead_speed_mps) ? "; none kept: the pass kept nothing" : ""));

  if (!qp_trouble.empty()) ctx.diagnostics.warn(where, "com-plan: the ZMP plan did not converge: " + qp_trouble);
  if (stages_dropping_landmarks > 0)
    ctx.diagnostics.warn(where, format("com-plan: %d result(s) dropped: following the plan would have moved the landmark error median "
                                       "by more than %.1f cm (from %.1f cm)",
                                       stages_dropping_landmarks, 100 * options_.max_landmark_growth_m, 100 * landmarks_before));
  std::string repaired =
      repaired_rounds > 0 ? format("; %d repaired (plan pinned to the retargeted COM on %d samples, %d frames left as they came)",
                                   repaired_rounds, pinned_samples, kept_frames)
                          : std::string();
  if (rough_repairs > 0) repaired += format("; %d repair(s) not kept: rougher than the input (jitter)", rough_repairs);
  if (rounds_dropping_soles > 0)
    ctx.diagnostics.warn(where, format("com-plan: %d round(s) dropped: following the plan would have moved a held sole by more "
                                       "than %.1f mm%s", rounds_dropping_soles, 1e3 * options_.foot_tolerance_m, repaired.c_str()));
  if (results_dropping_drift > 0)
    ctx.diagnostics.warn(where, format("com-plan: %d result(s) dropped: a stance sole would have drifted more than %.1f mm from "
                                       "where its stance began", results_dropping_drift, 1e3 * drift_bound));
  if (unchanged)
    ctx.diagnostics.warn(where, "com-plan: no plan moved the ZMP into the support on more frames with the soles held; the "
                                "motion is left as it was");
  if (exported.outside > 0)
    ctx.diagnostics.warn(where, format("com-plan: the multibody ZMP stays more than 1 cm outside the support on %d of the "
                                       "stance frames (worst %.1f cm); the motion may be beyond this robot's balance",
                                       exported.outside, 100 * exported.worst_m));
  if (best_follow.missed_frames > 0)
    ctx.diagnostics.warn(where, format("com-plan: the COM could not follow the plan on %d frames (worst %.1f cm at %.2f s): "
                                       "joint or velocity limits, or reach with the soles held",
                                       best_follow.missed_frames, 100 * best_follow.max_miss_m, best_follow.max_miss_time_s));
  ctx.statistics.set("plan-violation-max", max_plan_violation, "m", "planned ZMP beyond its shrunk polygon (soft constraints), all rounds");
  ctx.statistics.set("clipped-offsets", clipped_offsets, "samples", "multibody corrections clipped to max_offset, all rounds");
  ctx.statistics.set("max-com-shift", best_shift, "m", "largest planned COM move from the retargeted COM");
  int stance_frames = 0;
  for (int f = 1; f + 1 < T; ++f) stance_frames += !frames.polygon[static_cast<std::size_t>(f)].empty();
  ctx.statistics.set("zmp-outside-before", before.outside, "frames", format("of %d stance frames, worst %.3f m", stance_frames, before.worst_m));
  ctx.statistics.set("zmp-outside-after", best.outside, "frames", format("stance frames, worst %.3f m", best.worst_m));
  ctx.statistics.set("repairs", repair_follows, "",
                     format("repair follows (a re-plan with the COM pinned where a held sole gave, then frames left as they came); %d "
                            "round(s) repaired, %d samples pinned, %d frames left as they came (in the repaired rounds), %d repair(s) "
                            "rougher than the input",
                            repaired_rounds, pinned_samples, kept_frames, rough_repairs));
  ctx.statistics.set("rounds", rounds, "", format("multibody correction rounds (%d QP active-set iterations); frames outside per round: %s", qp_iterations, round_outside.c_str()));
  ctx.statistics.set("frames-not-followed", best_follow.missed_frames, "frames",
                     format("|COM - plan| > %.3f m (worst %.3f m)", options_.follow_tolerance_m, best_follow.max_miss_m));
  ctx.statistics.set("max-sole-move", best_follow.max_foot_error_m, "m", "held soles' largest move");
  ctx.statistics.set("time-setup", ms_setup, "ms", "resampling, held soles, support polygons, the input's multibody ZMP");
  ctx.statistics.set("time-plan", ms_plan, "ms", "COM/ZMP QP, all rounds");
  ctx.statistics.set("time-follow", ms_follow, "ms", "COM-following IK, all rounds");
  ctx.statistics.set("time-zmp", ms_zmp, "ms", "multibody ZMP and scores, all rounds");
  ctx.statistics.set("time-whole-body", ms_whole_body, "ms", "whole-body stage");
}

}  // namespace rt
