#include "retarget/passes/ik_pass.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace {

constexpr std::array<std::array<Landmark, 3>, 2> kFootLandmarks = {
    std::array<Landmark, 3>{Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel},
    std::array<Landmark, 3>{Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel}};

// Which foot a landmark belongs to, or -1.
int foot_of(Landmark l) {
  for (int foot = 0; foot < 2; ++foot)
    for (Landmark f : kFootLandmarks[static_cast<std::size_t>(foot)])
      if (f == l) return foot;
  return -1;
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

void lock_stance_feet(const RobotModel& model, LandmarkTargets& targets, const ContactSchedule& contacts) {
  if (contacts.empty()) return;
  // Height of each mapped foot landmark point above its sole when the foot is flat (zero
  // configuration, where robot configs have their soles level).
  std::array<double, kLandmarkCount> height{};
  std::array<bool, kLandmarkCount> mapped{};
  {
    RobotData data(model);
    VecX q0 = VecX::Zero(model.nq());
    q0[3] = 1;
    update_kinematics(model, data, q0);
    for (const LandmarkTarget& lt : model.config().landmarks) {
      const int foot = foot_of(lt.landmark);
      if (foot < 0) continue;
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      const auto k = static_cast<std::size_t>(index(lt.landmark));
      height[k] = link_point(model, data, model.link_index(lt.link), lt.p_L_offset).z() -
                  link_point(model, data, sole.link, sole.p_L_center).z();
      mapped[k] = true;
    }
  }
  for (int foot = 0; foot < 2; ++foot) {
    const auto& c = contacts.in_contact[static_cast<std::size_t>(foot)];
    const int T = static_cast<int>(c.size());
    for (int begin = 0; begin < T;) {
      if (!c[static_cast<std::size_t>(begin)]) {
        ++begin;
        continue;
      }
      int end = begin;
      while (end < T && c[static_cast<std::size_t>(end)]) ++end;
      for (Landmark l : kFootLandmarks[static_cast<std::size_t>(foot)]) {
        LandmarkTrack& t = targets[l];
        if (!t.present) continue;
        for (int axis = 0; axis < 2; ++axis) {
          std::vector<double> v;
          for (int f = begin; f < end; ++f)
            if (t.valid(f)) v.push_back(t.p_W(axis, f));
          if (v.empty()) continue;
          const double m = median(std::move(v));
          for (int f = begin; f < end; ++f) t.p_W(axis, f) = m;
        }
        const auto k = static_cast<std::size_t>(index(l));
        if (mapped[k])
          for (int f = begin; f < end; ++f) t.p_W(2, f) = height[k];
        if (t.has_orientation) {
          Vec2 heading = Vec2::Zero();
          for (int f = begin; f < end; ++f) {
            const Vec3 x = t.R_W[static_cast<std::size_t>(f)] * Vec3::UnitX();
            if (t.valid(f) && x.head<2>().norm() > 1e-6) heading += x.head<2>().normalized();
          }
          if (heading.norm() > 1e-9) {
            const Quat flat(AngleAxis(std::atan2(heading.y(), heading.x()), Vec3::UnitZ()));
            for (int f = begin; f < end; ++f) t.R_W[static_cast<std::size_t>(f)] = flat;
          }
        }
      }
      begin = end;
    }
  }
}

std::vector<IkTarget> make_ik_targets(const RobotModel& model, const LandmarkIk& ik, const LandmarkTargets& targets,
                                      int frame, double interpolated_weight, std::vector<Landmark>* landmarks,
                                      const ContactSchedule* contacts, double stance_weight) {
  std::vector<IkTarget> out;
  if (landmarks) landmarks->clear();
  out.reserve(model.config().landmarks.size());
  for (const LandmarkTarget& lt : model.config().landmarks) {
    const LandmarkTrack& track = targets[lt.landmark];
    if (!track.present) continue;
    const SampleState state = track.state[static_cast<std::size_t>(frame)];
    if (state == SampleState::Missing) continue;
    double factor = state == SampleState::Interpolated ? interpolated_weight : 1.0;
    const int foot = foot_of(lt.landmark);
    if (contacts && !contacts->empty() && foot >= 0 &&
        contacts->in_contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(frame)])
      factor *= stance_weight;
    IkTarget t;
    t.link = model.link_index(lt.link);
    t.p_L = lt.p_L_offset;
    t.p_W = track.p_W.col(frame);
    t.weight = lt.weight * factor;
    if (lt.orientation_weight > 0 && track.has_orientation) {
      t.orientation_weight = lt.orientation_weight * factor;
      t.R_L_frame = ik.landmark_frame_in_link(t.link);
      t.R_W = track.R_W[static_cast<std::size_t>(frame)];
    }
    out.push_back(t);
    if (landmarks) landmarks->push_back(lt.landmark);
  }
  return out;
}

VecX initial_guess(const RobotModel& model, const LandmarkTargets& targets) {
  VecX q = model.standing_q();
  const LandmarkTrack& pelvis = targets[Landmark::Pelvis];
  if (pelvis.present) {
    q[0] = pelvis.p_W(0, 0);
    q[1] = pelvis.p_W(1, 0);
    if (pelvis.has_orientation) {
      const Vec3 x = pelvis.R_W[0] * Vec3::UnitX();
      const Quat yaw(AngleAxis(std::atan2(x.y(), x.x()), Vec3::UnitZ()));
      const Quat q_root = yaw * Quat(q[3], q[4], q[5], q[6]);
      q[3] = q_root.w();
      q[4] = q_root.x();
      q[5] = q_root.y();
      q[6] = q_root.z();
    }
  }
  return q;
}

IkPass::IkPass() {
  table_.add("max_iterations", options_.ik.max_iterations, "LM iterations per frame", {1, 10000, ""});
  table_.add("step_tolerance", options_.ik.step_tolerance, "[rad, m] stop when no coordinate moves more");
  table_.add("cost_tolerance", options_.ik.cost_tolerance, "stop when a step lowers the cost by less than this fraction");
  table_.add("regularization", options_.ik.regularization, "weight of the distance to the previous frame");
  table_.add("first_frame_iterations", options_.first_frame_iterations, "LM iterations for frame 0 (cold start)", {1, 100000, ""});
  table_.add("interpolated_weight", options_.interpolated_weight, "weight factor of gap-filled landmark samples");
  table_.add("stance_weight", options_.stance_weight, "weight factor of foot landmarks in stance (0: no stance lock)");
  table_.add("reseed_error", options_.reseed_error_m, "[m] frames above this RMS error are re-solved from the standing pose ...");
  table_.add("reseed_factor", options_.reseed_factor, "... when also above this multiple of the running median error");
}

void IkPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  const int T = clip.human.num_frames;
  if (T < 1) throw InputError(clip.human.source.path, "ik: the clip has no frames");
  if (!clip.targets[Landmark::Pelvis].present) throw InputError("--passes", "ik needs the scaled landmarks of the scale pass: put scale before ik");

  IkOptions first = options_.ik;
  first.max_iterations = options_.first_frame_iterations;
  first.regularization = options_.ik.regularization * 1e-3;  // nothing to stay close to yet
  const LandmarkIk ik_first(model, first);
  const LandmarkIk ik(model, options_.ik);
  const bool stance_lock = options_.stance_weight > 0 && !clip.contacts.empty();
  LandmarkTargets locked = clip.targets;  // the clip keeps the scaled human landmarks
  if (stance_lock) lock_stance_feet(model, locked, clip.contacts);
  const ContactSchedule* contacts = stance_lock ? &clip.contacts : nullptr;
  const double stance_weight = stance_lock ? options_.stance_weight : 1.0;
  std::vector<double> errors_so_far;
  int reseeded = 0;

  RobotMotion& motion = clip.motion;
  motion.fps = clip.human.fps;
  motion.q.resize(model.nq(), T);
  motion.landmark_error_m.resize(T);
  motion.worst_landmark.assign(static_cast<std::size_t>(T), -1);
  VecX q = initial_guess(model, locked);
  std::vector<int> worst_count(kLandmarkCount, 0);
  long iterations = 0;
  std::vector<Landmark> target_landmarks;
  for (int f = 0; f < T; ++f) {
    const std::vector<IkTarget> targets = make_ik_targets(model, ik, locked, f, options_.interpolated_weight,
                                                          &target_landmarks, contacts, stance_weight);
    if (targets.empty())
      throw InputError(clip.human.source.path + " frame " + std::to_string(f), "ik: no valid landmark to track");
    const VecX q_prev = q;
    IkResult r = (f == 0 ? ik_first : ik).solve(data, targets, q_prev, q);
    if (f > 0 && r.rms_error_m > options_.reseed_error_m) {
      const double typical = errors_so_far.empty() ? 0.0 : median(errors_so_far);
      if (r.rms_error_m > options_.reseed_factor * typical) {
        VecX q_seed = model.standing_q();
        q_seed.head<7>() = q_prev.head<7>();
        const IkResult r_seed = ik_first.solve(data, targets, q_seed, q_seed);
        if (r_seed.solver.cost < r.solver.cost) {
          q = q_seed;
          r = r_seed;
          ++reseeded;
        }
      }
    }
    if (f % 16 == 0) errors_so_far.push_back(r.rms_error_m);  // a sparse sample keeps the median cheap
    if (!q.allFinite()) throw InternalError(clip.human.source.path + " frame " + std::to_string(f) + ": ik produced non-finite values");
    iterations += r.solver.iterations;
    motion.q.col(f) = q;
    motion.landmark_error_m[f] = r.rms_error_m;
    if (r.worst_target >= 0) {
      const int l = index(target_landmarks[static_cast<std::size_t>(r.worst_target)]);
      motion.worst_landmark[static_cast<std::size_t>(f)] = l;
      ++worst_count[static_cast<std::size_t>(l)];
    }
  }
  motion.q_per_frame_ik = motion.q;

  std::vector<double> e(motion.landmark_error_m.data(), motion.landmark_error_m.data() + T);
  std::sort(e.begin(), e.end());
  const auto pct = [&](double p) { return e[static_cast<std::size_t>(std::floor(p * (T - 1)))]; };
  const int worst = static_cast<int>(std::max_element(worst_count.begin(), worst_count.end()) - worst_count.begin());
  ctx.statistics.set("landmark-error-median", pct(0.5), "m", "weighted RMS per frame");
  ctx.statistics.set("landmark-error-p95", pct(0.95), "m");
  ctx.statistics.set("landmark-error-max", e.back(), "m");
  ctx.statistics.set("worst-landmark-frames", worst_count[static_cast<std::size_t>(worst)], "frames",
                     std::string(landmark_name(static_cast<Landmark>(worst))));
  ctx.statistics.set("iterations-per-frame", static_cast<double>(iterations) / T);
  ctx.statistics.set("reseeded-frames", reseeded, "frames", "solved again from the standing pose");
  ctx.statistics.set("stance-lock", stance_lock ? 1 : 0, "", stance_lock ? "feet held in labelled stance" : "no contacts labelled");
}

}  // namespace rt
