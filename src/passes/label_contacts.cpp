#include "retarget/passes/label_contacts.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/ground.hpp"

namespace rt {

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(std::floor(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Horizontal speed of a landmark at frame f by central differences over valid neighbours.
double horizontal_speed(const LandmarkTrack& t, int f, int frames, double fps) {
  const int a = std::max(0, f - 1), b = std::min(frames - 1, f + 1);
  if (b == a || !t.valid(a) || !t.valid(b)) return 0;
  return (t.p_W.col(b).head<2>() - t.p_W.col(a).head<2>()).norm() * fps / (b - a);
}

}  // namespace

int merge_short_phases(std::vector<std::uint8_t>& labels, int min_frames) {
  int changed = 0;
  for (const std::uint8_t target : {std::uint8_t{0}, std::uint8_t{1}}) {  // fill swings, then drop stances
    std::size_t i = 0;
    while (i < labels.size()) {
      std::size_t j = i;
      while (j < labels.size() && labels[j] == labels[i]) ++j;
      // Only interior phases are merged: the clip's ends may legitimately be cut short.
      if (labels[i] == target && i > 0 && j < labels.size() && static_cast<int>(j - i) < min_frames) {
        std::fill(labels.begin() + static_cast<std::ptrdiff_t>(i), labels.begin() + static_cast<std::ptrdiff_t>(j),
                  static_cast<std::uint8_t>(1 - target));
        ++changed;
      }
      i = j;
    }
  }
  return changed;
}

namespace {

// Hysteresis labelling of one foot from per-frame height above its rest level and horizontal speed.
std::vector<std::uint8_t> hysteresis_labels(const std::vector<double>& height, const std::vector<double>& speed,
                                            const LabelContactsOptions& o) {
  std::vector<std::uint8_t> labels(height.size(), 0);
  bool in_contact = true;  // frame 0 assumption; corrected by the caller if the data disagree
  for (std::size_t f = 0; f < height.size(); ++f) {
    if (!std::isfinite(height[f])) {
      labels[f] = in_contact;  // no data: keep the current state
      continue;
    }
    if (in_contact)
      in_contact = !(height[f] > o.height_off_m || speed[f] > o.speed_off_mps);
    else
      in_contact = height[f] < o.height_on_m && speed[f] < o.speed_on_mps;
    labels[f] = in_contact;
  }
  return labels;
}

}  // namespace

ContactSchedule label_contacts(const HumanMotion& h, const LabelContactsOptions& o, Diagnostics& diag) {
  const int T = h.num_frames;
  ContactSchedule s;
  const std::array<std::array<Landmark, 3>, 2> feet = {
      std::array<Landmark, 3>{Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel},
      std::array<Landmark, 3>{Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel}};
  const char* names[2] = {"left", "right"};
  const int min_frames = std::max(1, static_cast<int>(std::lround(o.min_phase_s * h.fps)));
  for (int foot = 0; foot < 2; ++foot) {
    std::vector<std::uint8_t>& labels = s.in_contact[static_cast<std::size_t>(foot)];
    labels.assign(static_cast<std::size_t>(T), 0);
    // Resting height per landmark.
    std::array<double, 3> rest{};
    std::array<bool, 3> use{};
    for (int k = 0; k < 3; ++k) {
      const LandmarkTrack& t = h[feet[static_cast<std::size_t>(foot)][static_cast<std::size_t>(k)]];
      if (!t.present) continue;
      std::vector<double> z;
      for (int f = 0; f < T; ++f)
        if (t.valid(f)) z.push_back(t.p_W(2, f));
      if (z.empty()) continue;
      use[static_cast<std::size_t>(k)] = true;
      rest[static_cast<std::size_t>(k)] = percentile(std::move(z), o.rest_percentile);
    }
    std::vector<double> height(static_cast<std::size_t>(T), INFINITY), speed(static_cast<std::size_t>(T), 0.0);
    for (int f = 0; f < T; ++f) {
      // The lowest landmark (relative to its rest) decides; its speed must be low too.
      for (int k = 0; k < 3; ++k) {
        const LandmarkTrack& t = h[feet[static_cast<std::size_t>(foot)][static_cast<std::size_t>(k)]];
        if (!use[static_cast<std::size_t>(k)] || !t.valid(f)) continue;
        const double hk = t.p_W(2, f) - rest[static_cast<std::size_t>(k)];
        if (hk < height[static_cast<std::size_t>(f)]) {
          height[static_cast<std::size_t>(f)] = hk;
          speed[static_cast<std::size_t>(f)] = horizontal_speed(t, f, T, h.fps);
        }
      }
    }
    labels = hysteresis_labels(height, speed, o);
    merge_short_phases(labels, min_frames);
    if (T > 0 && !labels[0]) {
      diag.warn(h.source.path, std::string("label-contacts: the ") + names[foot] +
                                   " foot is not on the floor at frame 0; assuming contact there (paper §III)");
      for (int f = 0; f < std::min(T, min_frames); ++f) labels[static_cast<std::size_t>(f)] = 1;
    }
  }
  return s;
}

ContactSchedule label_robot_contacts(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                                     const LabelContactsOptions& o, Diagnostics& diag, const std::string& where) {
  const int T = static_cast<int>(q.cols());
  ContactSchedule s;
  std::array<std::vector<double>, 2> height, speed;
  std::array<std::vector<Vec2>, 2> centre;
  for (int foot = 0; foot < 2; ++foot) {
    height[static_cast<std::size_t>(foot)].resize(static_cast<std::size_t>(T));
    speed[static_cast<std::size_t>(foot)].resize(static_cast<std::size_t>(T));
    centre[static_cast<std::size_t>(foot)].resize(static_cast<std::size_t>(T));
  }
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q.col(f));
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      height[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] = lowest_sole_corner_z(model, data, foot);
      centre[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] = link_point(model, data, sole.link, sole.p_L_center).head<2>();
    }
  }
  const int min_frames = std::max(1, static_cast<int>(std::lround(o.min_phase_s * fps)));
  const char* names[2] = {"left", "right"};
  for (int foot = 0; foot < 2; ++foot) {
    auto& h = height[static_cast<std::size_t>(foot)];
    const double rest = percentile(h, o.rest_percentile);
    for (double& v : h) v -= rest;
    for (int f = 0; f < T; ++f) {
      const int a = std::max(0, f - 1), b = std::min(T - 1, f + 1);
      const auto& c = centre[static_cast<std::size_t>(foot)];
      speed[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] =
          b > a ? (c[static_cast<std::size_t>(b)] - c[static_cast<std::size_t>(a)]).norm() * fps / (b - a) : 0.0;
    }
    auto& labels = s.in_contact[static_cast<std::size_t>(foot)];
    labels = hysteresis_labels(h, speed[static_cast<std::size_t>(foot)], o);
    merge_short_phases(labels, min_frames);
    if (T > 0 && !labels[0]) {
      diag.warn(where, std::string("contacts: the ") + names[foot] + " foot is not on the floor at frame 0; assuming contact there");
      for (int f = 0; f < std::min(T, min_frames); ++f) labels[static_cast<std::size_t>(f)] = 1;
    }
  }
  return s;
}

LabelContactsPass::LabelContactsPass() {
  table_.add("height_on", options_.height_on_m, "[m] touch-down height above a landmark's resting height");
  table_.add("height_off", options_.height_off_m, "[m] lift-off height above a landmark's resting height");
  table_.add("speed_on", options_.speed_on_mps, "[m/s] horizontal speed below which a low foot is in contact");
  table_.add("speed_off", options_.speed_off_mps, "[m/s] horizontal speed above which a foot is not in contact");
  table_.add("min_phase", options_.min_phase_s, "[s] shortest stance or swing phase");
  table_.add("rest_percentile", options_.rest_percentile, "percentile of a landmark's height taken as resting height");
}

void LabelContactsPass::run(Clip& clip, PassContext& ctx) {
  clip.contacts = label_contacts(clip.human, options_, ctx.diagnostics);
  const int T = clip.human.num_frames;
  int phases[2] = {0, 0}, double_support = 0, flight = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const auto& l = clip.contacts.in_contact[static_cast<std::size_t>(foot)];
    for (int f = 0; f < T; ++f)
      if (l[static_cast<std::size_t>(f)] && (f == 0 || !l[static_cast<std::size_t>(f - 1)])) ++phases[foot];
  }
  for (int f = 0; f < T; ++f) {
    const bool a = clip.contacts.in_contact[0][static_cast<std::size_t>(f)], b = clip.contacts.in_contact[1][static_cast<std::size_t>(f)];
    double_support += a && b;
    flight += !a && !b;
  }
  ctx.statistics.set("stance-phases-left", phases[0]);
  ctx.statistics.set("stance-phases-right", phases[1]);
  ctx.statistics.set("double-support", T > 0 ? 100.0 * double_support / T : 0, "%");
  ctx.statistics.set("flight-frames", flight, "frames");
}

}  // namespace rt
