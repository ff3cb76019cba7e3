#include "retarget/passes/label_contacts.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/motion/floor_plane.hpp"

namespace rt {

namespace {

using Labels = std::vector<std::uint8_t>;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(std::floor(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Hysteresis labelling of one foot from per-frame height above its rest level and horizontal speed.
Labels hysteresis_labels(const FootTrack& t, double h_on, double h_off, double v_on, double v_off) {
  const std::size_t T = t.height_m.size();
  Labels labels(T, 0);
  bool in_contact = T > 0 && t.height_m[0] < h_off && t.speed_mps[0] < v_off;
  for (std::size_t f = 0; f < T; ++f) {
    const double h = t.height_m[f], v = t.speed_mps[f];
    if (std::isfinite(h)) {
      if (in_contact)
        in_contact = !(h > h_off || v > v_off);
      else
        in_contact = h < h_on && v < v_on;
    }  // no data: keep the current state
    labels[f] = in_contact;
  }
  return labels;
}

// How far a foot is from being in contact at frame f (1 = at the touch-down thresholds).
double contact_score(const FootTrack& t, std::size_t f, double h_on, double v_on) {
  const double h = t.height_m[f];
  if (!std::isfinite(h)) return INFINITY;
  return std::max(h / h_on, t.speed_mps[f] / v_on);
}

// [begin, end) of the phase of `labels` that contains frame f.
std::pair<int, int> phase_around(const Labels& labels, int f) {
  int a = f, b = f;
  while (a > 0 && labels[static_cast<std::size_t>(a - 1)] == labels[static_cast<std::size_t>(f)]) --a;
  while (b < static_cast<int>(labels.size()) && labels[static_cast<std::size_t>(b)] == labels[static_cast<std::size_t>(f)]) ++b;
  return {a, b};
}

// Which foot stands on each frame of a run [a, b) in which neither foot passed the contact
// thresholds: the one closer to them (lower contact score), with a penalty per change of foot so
// that near-equal feet do not alternate (two-state Viterbi). `enter` / `leave` are the feet in
// contact just before and after the run (-1: no constraint). A foot is only handed the weight in
// the middle of the run for at least `min_frames`; shorter pieces stay with the foot around them.
// Per frame, because a run between two stances of one foot can belong to the other foot: a kick
// (4 m/s, 8 cm up in a LAFAN1 fight) over a foot that stands still just above the thresholds.
std::vector<int> assign_run(const std::array<FootTrack, 2>& feet, int a, int b, int enter, int leave, double h_on,
                            double v_on, int min_frames) {
  const int n = b - a;
  constexpr double kSwitch = 2.0;  // [contact-score units] cost of handing the weight over
  auto cost = [&](int foot, int f) {
    return std::min(contact_score(feet[static_cast<std::size_t>(foot)], static_cast<std::size_t>(f), h_on, v_on), 1e3);
  };
  std::vector<std::array<double, 2>> acc(static_cast<std::size_t>(n));
  std::vector<std::array<int, 2>> from(static_cast<std::size_t>(n));
  for (int s = 0; s < 2; ++s) acc[0][static_cast<std::size_t>(s)] = cost(s, a) + (enter >= 0 && s != enter ? kSwitch : 0.0);
  for (int i = 1; i < n; ++i)
    for (int s = 0; s < 2; ++s) {
      const double stay = acc[static_cast<std::size_t>(i - 1)][static_cast<std::size_t>(s)];
      const double change = acc[static_cast<std::size_t>(i - 1)][static_cast<std::size_t>(1 - s)] + kSwitch;
      from[static_cast<std::size_t>(i)][static_cast<std::size_t>(s)] = stay <= change ? s : 1 - s;
      acc[static_cast<std::size_t>(i)][static_cast<std::size_t>(s)] = std::min(stay, change) + cost(s, a + i);
    }
  std::array<double, 2> end = acc.back();
  if (leave >= 0) end[static_cast<std::size_t>(1 - leave)] += kSwitch;
  std::vector<int> owner(static_cast<std::size_t>(n));
  owner.back() = end[1] < end[0] ? 1 : 0;
  for (int i = n - 1; i > 0; --i)
    owner[static_cast<std::size_t>(i - 1)] = from[static_cast<std::size_t>(i)][static_cast<std::size_t>(owner[static_cast<std::size_t>(i)])];
  // Interior pieces shorter than min_frames go to the foot around them.
  for (int i = 0; i < n;) {
    int j = i;
    while (j < n && owner[static_cast<std::size_t>(j)] == owner[static_cast<std::size_t>(i)]) ++j;
    if (i > 0 && j < n && j - i < min_frames)
      std::fill(owner.begin() + i, owner.begin() + j, 1 - owner[static_cast<std::size_t>(i)]);
    i = j;
  }
  return owner;
}

}  // namespace

int merge_short_phases(Labels& labels, int min_frames) {
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

ContactLabelling label_feet(const std::array<FootTrack, 2>& feet, double fps_src, double size_m, const LabelContactsOptions& o) {
  ContactLabelling out;
  out.size_m = size_m;
  const int T = static_cast<int>(feet[0].height_m.size());
  const double h_on = o.height_on * size_m, h_off = o.height_off * size_m, h_air = o.airborne_height * size_m;
  const double v_on = o.speed_on * size_m, v_off = o.speed_off * size_m;
  const int min_frames = std::max(1, static_cast<int>(std::lround(o.min_phase_s * fps_src)));
  const int ds_frames = std::max(1, static_cast<int>(std::lround(o.min_double_support_s * fps_src)));
  std::array<Labels, 2>& L = out.schedule.in_contact;

  // 1. Hysteresis per foot, short phases merged.
  for (int foot = 0; foot < 2; ++foot) {
    L[static_cast<std::size_t>(foot)] = hysteresis_labels(feet[static_cast<std::size_t>(foot)], h_on, h_off, v_on, v_off);
    merge_short_phases(L[static_cast<std::size_t>(foot)], min_frames);
  }
  auto in = [&](int foot, int f) { return L[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] != 0; };
  auto set = [&](int foot, int a, int b) {
    for (int f = std::max(0, a); f < std::min(T, b); ++f) L[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] = 1;
  };

  // 2. Runs without a stance foot: flights, or given to the better-placed foot.
  for (int a = 0; a < T;) {
    if (in(0, a) || in(1, a)) {
      ++a;
      continue;
    }
    int b = a;
    while (b < T && !in(0, b) && !in(1, b)) ++b;
    int airborne = 0;
    for (int f = a; f < b; ++f)
      airborne += feet[0].height_m[static_cast<std::size_t>(f)] > h_air && feet[1].height_m[static_cast<std::size_t>(f)] > h_air;
    if (2 * airborne >= b - a) {
      ++out.flight_phases;
      out.flight_frames += b - a;
      a = b;
      continue;
    }
    out.filled_frames += b - a;
    // The foot on the floor next to the run (-1 when both are: no constraint).
    auto adjacent = [&](int f) { return in(0, f) && in(1, f) ? -1 : in(0, f) ? 0 : 1; };
    const std::vector<int> owner =
        assign_run(feet, a, b, a > 0 ? adjacent(a - 1) : -1, b < T ? adjacent(b) : -1, h_on, v_on, min_frames);
    for (int f = a; f < b; ++f) set(owner[static_cast<std::size_t>(f - a)], f, f + 1);
    a = b;
  }

  // 3. Minimum double support where one foot lifts off while the other is down.
  for (int foot = 0; foot < 2; ++foot) {
    const int other = 1 - foot;
    for (int e = 1; e < T; ++e) {
      if (!(in(foot, e - 1) && !in(foot, e))) continue;  // foot lifts off at e
      if (!in(other, e)) continue;  // no transfer: a flight or a hop follows
      // Overlap so far: frames before e where both are down, counted back from e.
      int overlap = 0;
      while (e - 1 - overlap >= 0 && in(foot, e - 1 - overlap) && in(other, e - 1 - overlap)) ++overlap;
      if (overlap >= ds_frames) continue;
      int need = ds_frames - overlap;
      // Widen forwards: the lifting foot stays down longer (not into its next stance, keeping a swing).
      const auto [swing_a, swing_b] = phase_around(L[static_cast<std::size_t>(foot)], e);
      const int room_fwd = swing_b < T ? std::max(0, swing_b - swing_a - min_frames) : swing_b - swing_a;
      // Widen backwards: the landing foot lands earlier (not into its previous stance).
      int other_start = e;
      while (other_start > 0 && in(other, other_start - 1)) --other_start;
      int room_back = 0;
      if (other_start > 0) {
        const auto [pa, pb] = phase_around(L[static_cast<std::size_t>(other)], other_start - 1);
        room_back = pa > 0 ? std::max(0, pb - pa - min_frames) : pb - pa;
      }
      int fwd = std::min((need + 1) / 2, room_fwd), back = std::min(need - fwd, room_back);
      fwd = std::min(need - back, room_fwd);
      if (fwd + back == 0) continue;
      set(foot, e, e + fwd);
      set(other, other_start - back, other_start);
      ++out.widened_transfers;
      e += fwd;
    }
  }
  return out;
}

ContactLabelling label_contacts(const HumanMotion& h, const LabelContactsOptions& o) {
  const int T = h.num_frames;
  const std::array<std::array<Landmark, 3>, 2> feet = {
      std::array<Landmark, 3>{Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel},
      std::array<Landmark, 3>{Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel}};
  double leg = human_leg_length(h);
  if (!(leg > 0.2)) leg = 0.85;  // no legs to measure: a typical adult's
  const double fps_src = h.fps * h.time_scale;
  std::array<FootTrack, 2> tracks;
  for (int foot = 0; foot < 2; ++foot) {
    FootTrack& ft = tracks[static_cast<std::size_t>(foot)];
    ft.height_m.assign(static_cast<std::size_t>(T), INFINITY);
    ft.speed_mps.assign(static_cast<std::size_t>(T), 0.0);
    for (Landmark l : feet[static_cast<std::size_t>(foot)]) {
      const LandmarkTrack& t = h[l];
      if (!t.present) continue;
      std::vector<double> z;
      for (int f = 0; f < T; ++f)
        if (t.valid(f)) z.push_back(t.p_W(2, f));
      if (z.empty()) continue;
      const double rest = percentile(std::move(z), o.rest_percentile);
      // The lowest landmark (relative to its rest) decides; its speed must be low too.
      for (int f = 0; f < T; ++f) {
        if (!t.valid(f)) continue;
        const double hk = t.p_W(2, f) - rest;
        if (hk >= ft.height_m[static_cast<std::size_t>(f)]) continue;
        ft.height_m[static_cast<std::size_t>(f)] = hk;
        const int a = std::max(0, f - 1), b = std::min(T - 1, f + 1);
        ft.speed_mps[static_cast<std::size_t>(f)] =
            b > a && t.valid(a) && t.valid(b) ? (t.p_W.col(b).head<2>() - t.p_W.col(a).head<2>()).norm() * fps_src / (b - a) : 0.0;
      }
    }
  }
  return label_feet(tracks, fps_src, leg, o);
}

ContactSchedule label_robot_contacts(const RobotModel& model, RobotData& data, const MatX& q, double fps,
                                     const LabelContactsOptions& o, Diagnostics& diag, const std::string& where) {
  const int T = static_cast<int>(q.cols());
  std::array<FootTrack, 2> tracks;
  std::array<std::vector<Vec2>, 2> centre;
  for (int foot = 0; foot < 2; ++foot) {
    tracks[static_cast<std::size_t>(foot)].height_m.resize(static_cast<std::size_t>(T));
    tracks[static_cast<std::size_t>(foot)].speed_mps.resize(static_cast<std::size_t>(T));
    centre[static_cast<std::size_t>(foot)].resize(static_cast<std::size_t>(T));
  }
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q.col(f));
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      tracks[static_cast<std::size_t>(foot)].height_m[static_cast<std::size_t>(f)] = lowest_sole_corner_z(model, data, foot);
      centre[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f)] = link_point(model, data, sole.link, sole.p_L_center).head<2>();
    }
  }
  for (int foot = 0; foot < 2; ++foot) {
    auto& h = tracks[static_cast<std::size_t>(foot)].height_m;
    const double rest = percentile(h, o.rest_percentile);
    for (double& v : h) v -= rest;
    const auto& c = centre[static_cast<std::size_t>(foot)];
    for (int f = 0; f < T; ++f) {
      const int a = std::max(0, f - 1), b = std::min(T - 1, f + 1);
      tracks[static_cast<std::size_t>(foot)].speed_mps[static_cast<std::size_t>(f)] =
          b > a ? (c[static_cast<std::size_t>(b)] - c[static_cast<std::size_t>(a)]).norm() * fps / (b - a) : 0.0;
    }
  }
  // The standing root height stands in for the leg length the thresholds are relative to.
  const double size = std::max(0.3, model.standing_q()[2]);
  ContactLabelling l = label_feet(tracks, fps, size, o);
  if (l.flight_frames > T / 5)
    diag.warn(where, format("contacts: %d of %d frames have both feet off the floor", l.flight_frames, T));
  return l.schedule;
}

LabelContactsPass::LabelContactsPass() {
  table_.add("height_on", options_.height_on, "[leg lengths] touch-down height above a landmark's resting height");
  table_.add("height_off", options_.height_off, "[leg lengths] lift-off height above a landmark's resting height");
  table_.add("speed_on", options_.speed_on, "[leg lengths/s, source time] horizontal speed below which a low foot is in contact");
  table_.add("speed_off", options_.speed_off, "[leg lengths/s, source time] horizontal speed above which a foot is not in contact");
  table_.add("min_phase", options_.min_phase_s, "[s, source time] shortest stance or swing phase", {0, 10, "s"});
  table_.add("min_double_support", options_.min_double_support_s, "[s, source time] double support at every weight transfer", {0, 10, "s"});
  table_.add("airborne_height", options_.airborne_height, "[leg lengths] both feet above this: a flight phase");
  table_.add("rest_percentile", options_.rest_percentile, "percentile of a landmark's height taken as resting height");
}

void LabelContactsPass::run(Clip& clip, PassContext& ctx) {
  const LabelContactsOptions& o = options_;
  require_input(o.height_on > 0 && o.height_off >= o.height_on && o.speed_on > 0 && o.speed_off >= o.speed_on, "label-contacts",
                "options need 0 < height_on <= height_off and 0 < speed_on <= speed_off");
  require_input(o.min_phase_s >= 0 && o.min_phase_s <= 10 && o.min_double_support_s >= 0 && o.min_double_support_s <= 2 &&
                    o.airborne_height > 0 && o.rest_percentile >= 0 && o.rest_percentile <= 1,
                "label-contacts", "options need min_phase in [0, 10] s, min_double_support in [0, 2] s, airborne_height > 0, "
                                  "rest_percentile in [0, 1]");
  const ContactLabelling l = label_contacts(clip.human, o);
  clip.contacts = l.schedule;
  const int T = clip.human.num_frames;
  int phases[2] = {0, 0}, double_support = 0, no_stance = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const auto& c = clip.contacts.in_contact[static_cast<std::size_t>(foot)];
    for (int f = 0; f < T; ++f)
      if (c[static_cast<std::size_t>(f)] && (f == 0 || !c[static_cast<std::size_t>(f - 1)])) ++phases[foot];
  }
  for (int f = 0; f < T; ++f) {
    const bool a = clip.contacts.in_contact[0][static_cast<std::size_t>(f)], b = clip.contacts.in_contact[1][static_cast<std::size_t>(f)];
    double_support += a && b;
    no_stance += !a && !b;
  }
  if (T > 0 && no_stance > T / 5)
    ctx.diagnostics.warn(clip.human.source.path,
                         format("label-contacts: %.0f%% of the frames have both feet in the air (%d flight phases); check the "
                                "floor and the source units (retarget inspect CLIP)",
                                100.0 * no_stance / T, l.flight_phases));
  ctx.statistics.set("leg-length", l.size_m, "m", "thresholds are relative to it");
  ctx.statistics.set("stance-phases-left", phases[0]);
  ctx.statistics.set("stance-phases-right", phases[1]);
  ctx.statistics.set("double-support", T > 0 ? 100.0 * double_support / T : 0, "%");
  ctx.statistics.set("flight-phases", l.flight_phases, "", "both feet clearly airborne");
  ctx.statistics.set("flight-frames", l.flight_frames, "frames");
  ctx.statistics.set("filled-frames", l.filled_frames, "frames", "no foot under the thresholds, not airborne: given to the lower foot");
  ctx.statistics.set("widened-transfers", l.widened_transfers, "", "weight transfers widened to the minimum double support");
}

}  // namespace rt
