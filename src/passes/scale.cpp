#include "retarget/passes/scale.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace {

// Preferred parents, nearest first.
std::vector<Landmark> parent_candidates(Landmark l) {
  using L = Landmark;
  switch (l) {
    case L::Pelvis: return {};
    case L::Spine: return {L::Pelvis};
    case L::Chest: return {L::Spine, L::Pelvis};
    case L::Neck: return {L::Chest, L::Spine, L::Pelvis};
    case L::Head: return {L::Neck, L::Chest, L::Spine, L::Pelvis};
    case L::LeftHip: case L::RightHip: return {L::Pelvis};
    case L::LeftKnee: return {L::LeftHip, L::Pelvis};
    case L::RightKnee: return {L::RightHip, L::Pelvis};
    case L::LeftAnkle: return {L::LeftKnee, L::LeftHip, L::Pelvis};
    case L::RightAnkle: return {L::RightKnee, L::RightHip, L::Pelvis};
    case L::LeftToe: case L::LeftHeel: return {L::LeftAnkle, L::LeftKnee, L::Pelvis};
    case L::RightToe: case L::RightHeel: return {L::RightAnkle, L::RightKnee, L::Pelvis};
    case L::LeftShoulder: case L::RightShoulder: return {L::Chest, L::Neck, L::Spine, L::Pelvis};
    case L::LeftElbow: return {L::LeftShoulder, L::Chest, L::Pelvis};
    case L::RightElbow: return {L::RightShoulder, L::Chest, L::Pelvis};
    case L::LeftWrist: return {L::LeftElbow, L::LeftShoulder, L::Pelvis};
    case L::RightWrist: return {L::RightElbow, L::RightShoulder, L::Pelvis};
    case L::LeftHand: return {L::LeftWrist, L::LeftElbow, L::Pelvis};
    case L::RightHand: return {L::RightWrist, L::RightElbow, L::Pelvis};
    case L::Count: break;
  }
  return {};
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Median human distance between two landmarks over the frames where both are valid.
double human_length(const HumanMotion& h, Landmark a, Landmark b) {
  std::vector<double> d;
  d.reserve(static_cast<std::size_t>(h.num_frames));
  for (int f = 0; f < h.num_frames; ++f)
    if (h[a].valid(f) && h[b].valid(f)) d.push_back((h[a].p_W.col(f) - h[b].p_W.col(f)).norm());
  return median(std::move(d));
}

// Robot landmark points at the zero configuration (root at the origin, joints 0), for the landmarks
// the robot maps.
std::array<std::optional<Vec3>, kLandmarkCount> robot_points(const RobotModel& model, RobotData& data) {
  VecX q0 = VecX::Zero(model.nq());
  q0[3] = 1;
  update_kinematics(model, data, q0);
  std::array<std::optional<Vec3>, kLandmarkCount> out;
  for (const LandmarkTarget& t : model.config().landmarks)
    out[static_cast<std::size_t>(index(t.landmark))] = link_point(model, data, model.link_index(t.link), t.p_L_offset);
  return out;
}

}  // namespace

std::optional<Landmark> scale_parent(const HumanMotion& human, Landmark l) {
  for (Landmark p : parent_candidates(l))
    if (human.has(p)) return p;
  return std::nullopt;
}

ScalePass::ScalePass() {
  table_.add("min_ratio", options_.min_ratio, "smallest allowed segment ratio robot/human");
  table_.add("max_ratio", options_.max_ratio, "largest allowed segment ratio robot/human");
  table_.add("min_segment", options_.min_segment_m, "[m] shorter human segments take the leg ratio");
}

void ScalePass::run(Clip& clip, PassContext& ctx) {
  const HumanMotion& h = clip.human;
  const RobotModel& model = ctx.model();
  if (!h.has(Landmark::Pelvis))
    throw InputError(h.source.path, "scale: the motion has no pelvis landmark, nothing to anchor the robot to");
  const auto robot = robot_points(model, ctx.data());
  auto robot_len = [&](Landmark a, Landmark b) -> std::optional<double> {
    const auto& pa = robot[static_cast<std::size_t>(index(a))];
    const auto& pb = robot[static_cast<std::size_t>(index(b))];
    if (!pa || !pb) return std::nullopt;
    return (*pa - *pb).norm();
  };

  // Leg ratio: hip -> knee -> ankle of both legs, robot over human.
  double human_leg = 0, robot_leg = 0;
  int legs = 0;
  for (auto [hip, knee, ankle] : {std::array<Landmark, 3>{Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle},
                                  std::array<Landmark, 3>{Landmark::RightHip, Landmark::RightKnee, Landmark::RightAnkle}}) {
    const auto rt = robot_len(hip, knee), rs = robot_len(knee, ankle);
    if (!h.has(hip) || !h.has(knee) || !h.has(ankle) || !rt || !rs) continue;
    human_leg += human_length(h, hip, knee) + human_length(h, knee, ankle);
    robot_leg += *rt + *rs;
    ++legs;
  }
  if (legs == 0 || human_leg < options_.min_segment_m)
    throw InputError(h.source.path, "scale: need hip, knee and ankle landmarks of at least one leg, on the human and the robot");
  double leg_ratio = robot_leg / human_leg;
  if (leg_ratio < options_.min_ratio || leg_ratio > options_.max_ratio) {
    ctx.diagnostics.warn(h.source.path, format("scale: leg ratio %.3f clamped to [%g, %g] (check the source units)",
                                               leg_ratio, options_.min_ratio, options_.max_ratio));
    leg_ratio = std::clamp(leg_ratio, options_.min_ratio, options_.max_ratio);
  }

  LandmarkTargets& out = clip.targets;
  out.height_scale = leg_ratio;
  out.scale.fill(leg_ratio);
  // Ratio of each landmark's segment to its parent.
  for (Landmark l : all_landmarks()) {
    const auto parent = scale_parent(h, l);
    if (!parent || !h.has(l)) continue;
    const double hl = human_length(h, *parent, l);
    const auto rl = robot_len(*parent, l);
    double ratio = leg_ratio;
    if (rl && hl >= options_.min_segment_m) {
      ratio = *rl / hl;
      if (ratio < options_.min_ratio || ratio > options_.max_ratio) {
        ctx.diagnostics.warn(h.source.path, format("scale: segment %s-%s ratio %.3f clamped to [%g, %g]",
                                                   std::string(landmark_name(*parent)).c_str(),
                                                   std::string(landmark_name(l)).c_str(), ratio,
                                                   options_.min_ratio, options_.max_ratio));
        ratio = std::clamp(ratio, options_.min_ratio, options_.max_ratio);
      }
    }
    out.scale[static_cast<std::size_t>(index(l))] = ratio;
  }

  // Rebuild every frame root-relatively, parents before children (enum order is topological).
  for (Landmark l : all_landmarks()) {
    const LandmarkTrack& src = h[l];
    LandmarkTrack& dst = out[l];
    dst = src;  // validity, orientation
    if (!src.present) continue;
    const auto parent = scale_parent(h, l);
    if (!parent) {
      dst.p_W = src.p_W * leg_ratio;  // the root: positions and height scaled by the leg ratio
      continue;
    }
    const double ratio = out.scale[static_cast<std::size_t>(index(l))];
    dst.p_W = out[*parent].p_W + ratio * (src.p_W - h[*parent].p_W);
  }

  ctx.statistics.set("leg-ratio", leg_ratio, "", "robot leg length / human leg length");
  ctx.statistics.set("human-leg-length", human_leg / legs, "m");
  ctx.statistics.set("robot-leg-length", robot_leg / legs, "m");
  for (Landmark l : {Landmark::LeftKnee, Landmark::LeftAnkle, Landmark::LeftElbow, Landmark::LeftWrist, Landmark::Head})
    if (h.has(l)) ctx.statistics.set("ratio-" + std::string(landmark_name(l)), out.scale[static_cast<std::size_t>(index(l))]);
}

}  // namespace rt
