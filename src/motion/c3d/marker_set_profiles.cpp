#include "retarget/motion/c3d/marker_set_profiles.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/c3d/joint_centre_models.hpp"
#include "retarget/motion/c3d/rigid_cluster.hpp"

namespace rt {

namespace {

using Track = LandmarkTrack;
using Tracks = std::array<Track, kLandmarkCount>;

constexpr double kDefaultMarkerDiameter = 0.014;  // Plug-in Gait default
constexpr double kDefaultKneeWidth = 0.100;
constexpr double kDefaultAnkleWidth = 0.070;
constexpr double kDefaultElbowWidth = 0.070;
constexpr double kDefaultWristThickness = 0.040;
constexpr double kDefaultShoulderOffset = 0.050;

SampleState combine(SampleState a, SampleState b) {
  if (a == SampleState::Missing || b == SampleState::Missing) return SampleState::Missing;
  if (a == SampleState::Interpolated || b == SampleState::Interpolated) return SampleState::Interpolated;
  return SampleState::Measured;
}

bool ok(const Track& t) { return t.present; }
Vec3 at(const Track& t, int f) { return t.p_W.col(f); }

// Evaluates `fn(frame)` where every input is valid; the result is valid where fn succeeds and
// inherits the weakest input state (a reconstructed input makes the output Interpolated).
template <class F>
Track build(int frames, const std::vector<const Track*>& inputs, F&& fn) {
  Track t;
  for (const Track* x : inputs)
    if (!x || !x->present) return t;
  t.present = true;
  t.p_W.setZero(3, frames);
  t.state.assign(static_cast<std::size_t>(frames), SampleState::Missing);
  for (int f = 0; f < frames; ++f) {
    SampleState s = SampleState::Measured;
    for (const Track* x : inputs) s = combine(s, x->state[static_cast<std::size_t>(f)]);
    if (s == SampleState::Missing) continue;
    const std::optional<Vec3> v = fn(f);
    if (!v || !v->allFinite()) continue;
    t.p_W.col(f) = *v;
    t.state[static_cast<std::size_t>(f)] = s;
  }
  return t;
}

Track mean_track(int frames, const std::vector<const Track*>& inputs) {
  std::vector<const Track*> in;
  for (const Track* t : inputs)
    if (t && t->present) in.push_back(t);
  if (in.empty()) return {};
  return build(frames, in, [&](int f) -> std::optional<Vec3> {
    Vec3 s = Vec3::Zero();
    for (const Track* t : in) s += at(*t, f);
    return s / static_cast<double>(in.size());
  });
}

Track marker_track(const MarkerTrajectories& ms, int index) {
  Track t;
  if (index < 0) return t;
  const MarkerTrajectory& m = ms.markers[static_cast<std::size_t>(index)];
  t.present = true;
  t.p_W = m.p_F;
  t.state = m.state;
  return t;
}

// Median over the frames where `fn` yields a value.
template <class F>
std::optional<double> median_over_frames(int frames, F&& fn) {
  std::vector<double> v;
  for (int f = 0; f < frames; ++f)
    if (const std::optional<double> x = fn(f)) v.push_back(*x);
  if (v.empty()) return std::nullopt;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Markers named <prefix><digits> for any of the prefixes.
std::vector<int> numbered(const MarkerTrajectories& ms, std::initializer_list<std::string> prefixes) {
  std::vector<int> out;
  for (std::size_t i = 0; i < ms.markers.size(); ++i) {
    const std::string& n = ms.markers[i].name;
    for (const std::string& p : prefixes)
      if (n.size() > p.size() && starts_with(n, p) && all_digits(std::string_view(n).substr(p.size()))) {
        out.push_back(static_cast<int>(i));
        break;
      }
  }
  return out;
}

std::string landmark_list(const std::vector<Landmark>& ls) {
  std::vector<std::string> names;
  for (Landmark l : ls) names.emplace_back(landmark_name(l));
  return join(names, ", ");
}

void add_method(MarkerLandmarks& out, Landmark l, const std::string& how) {
  out.methods.push_back(std::string(landmark_name(l)) + ": " + how);
}

// ---- anatomical markers (Plug-in Gait, CAST / Qualisys and variants) ----------------------------

enum SideRole { ASIS, PSIS, HJC, THI, KNE, KNM, KJC, TIB, ANK, MED, AJC, HEE, TOE, MT1, MT5, SHO, SJC, ELB, ELM, EJC,
                WRA, WRB, WJC, FIN, HM5, FHD, BHD, kSideRoleCount };
enum CentralRole { SACR, C7, T10, CLAV, STRN, HEAD, kCentralRoleCount };

struct Aliases {
  const char* role;
  std::array<const char*, 12> patterns;  // "{S}" is the side letter; unused slots are nullptr
};

// Alias tables: constant data (no mutable state). First match wins, so the most specific
// spelling comes first.
constexpr Aliases kSideAliases[kSideRoleCount] = {
    {"ASIS", {"{S}ASI", "{S}_IAS", "{S}IAS", "{S}ASIS", "{S}_ASIS"}},
    {"PSIS", {"{S}PSI", "{S}_IPS", "{S}IPS", "{S}PSIS", "{S}_PSIS"}},
    {"HJC", {"{S}HJC", "{S}_HJC", "{S}HIPJC"}},
    {"THI", {"{S}THI", "{S}THIGH"}},
    {"KNE", {"{S}KNE", "{S}_FLE", "{S}FLE", "{S}LFC", "{S}_LFC", "{S}KNEE", "{S}LKNE", "{S}LEK"}},
    {"KNM", {"{S}KNM", "{S}_FME", "{S}FME", "{S}MFC", "{S}_MFC", "{S}MKNE", "{S}KNEM", "{S}MEK"}},
    {"KJC", {"{S}KJC", "{S}_KJC", "{S}KNEEJC"}},
    {"TIB", {"{S}TIB", "{S}SHANK", "{S}TIBIA"}},
    {"ANK", {"{S}ANK", "{S}_FAL", "{S}FAL", "{S}LMAL", "{S}_LMAL", "{S}ANKLE", "{S}LANK", "{S}LMA"}},
    {"MED", {"{S}MED", "{S}_TAM", "{S}TAM", "{S}MMAL", "{S}_MMAL", "{S}MANK", "{S}ANKM", "{S}MMA"}},
    {"AJC", {"{S}AJC", "{S}_AJC", "{S}ANKJC"}},
    {"HEE", {"{S}HEE", "{S}_FCC", "{S}FCC", "{S}CAL", "{S}_CAL", "{S}HEEL", "{S}_HEE"}},
    {"TOE", {"{S}TOE", "{S}_FM2", "{S}FM2", "{S}_TOE"}},
    {"MT1", {"{S}_FM1", "{S}FM1", "{S}MT1", "{S}MH1", "{S}MET1"}},
    {"MT5", {"{S}_FM5", "{S}FM5", "{S}MT5", "{S}MH5", "{S}MET5", "{S}MT2", "{S}MET"}},
    {"SHO", {"{S}SHO", "{S}_SAE", "{S}_SAJ", "{S}SAE", "{S}SAJ", "{S}CAJ", "{S}_CAJ", "{S}ACR", "{S}ACROM",
             "{S}SHOULDER", "{S}_AC", "{S}SHOULD"}},
    {"SJC", {"{S}SJC", "{S}_SJC", "{S}SHOJC", "{S}GHJC"}},
    {"ELB", {"{S}ELB", "{S}_HLE", "{S}HLE", "{S}LEL", "{S}ELBL", "{S}LEPI", "{S}ELBOW"}},
    {"ELM", {"{S}_HME", "{S}HME", "{S}MEL", "{S}ELBM", "{S}MEPI", "{S}MELB"}},
    {"EJC", {"{S}EJC", "{S}_EJC", "{S}ELBJC"}},
    {"WRA", {"{S}WRA", "{S}_RSP", "{S}RSP", "{S}WRR"}},
    {"WRB", {"{S}WRB", "{S}_USP", "{S}USP", "{S}_UHE", "{S}UHE", "{S}WRU"}},
    {"WJC", {"{S}WJC", "{S}_WJC", "{S}WRJC"}},
    {"FIN", {"{S}FIN", "{S}_HM2", "{S}HM2", "{S}HAND"}},
    {"HM5", {"{S}_HM5", "{S}HM5"}},
    {"FHD", {"{S}FHD", "{S}_HDF", "{S}HDF", "{S}AH", "{S}FH"}},
    {"BHD", {"{S}BHD", "{S}_HDB", "{S}HDB", "{S}PH", "{S}BH"}},
};
constexpr Aliases kCentralAliases[kCentralRoleCount] = {
    {"SACR", {"SACR", "SACRUM", "SAC", "S1", "V_SACR", "VSAC"}},
    {"C7", {"C7", "CV7", "C7_"}},
    {"T10", {"T10", "TV10", "T8", "TV8", "T12", "TV12"}},
    {"CLAV", {"CLAV", "SJN", "SNJ", "IJ", "JN", "CLAVICLE"}},
    {"STRN", {"STRN", "SXS", "PX", "XP", "STERNUM"}},
    {"HEAD", {"HEAD", "HDT", "HEADTOP", "VERTEX", "TOPHEAD"}},
};

std::string expand(const char* pattern, char side) {
  std::string s(pattern);
  const auto k = s.find("{S}");
  if (k != std::string::npos) s.replace(k, 3, std::string(1, side));
  return s;
}

struct RoleMatch {
  int marker = -1;
  std::string alias;  // the spelling that matched
};

RoleMatch match_role(const MarkerTrajectories& ms, const Aliases& a, char side) {
  for (const char* p : a.patterns) {
    if (!p) break;
    const std::string name = expand(p, side);
    const int i = ms.find(name);
    if (i >= 0) return {i, name};
  }
  return {};
}

constexpr char kSideLetter[2] = {'L', 'R'};
constexpr double kSideSign[2] = {+1.0, -1.0};  // +y is the subject's left in the pelvis frame
constexpr Landmark kHip[2] = {Landmark::LeftHip, Landmark::RightHip};
constexpr Landmark kKnee[2] = {Landmark::LeftKnee, Landmark::RightKnee};
constexpr Landmark kAnkle[2] = {Landmark::LeftAnkle, Landmark::RightAnkle};
constexpr Landmark kToe[2] = {Landmark::LeftToe, Landmark::RightToe};
constexpr Landmark kHeel[2] = {Landmark::LeftHeel, Landmark::RightHeel};
constexpr Landmark kShoulder[2] = {Landmark::LeftShoulder, Landmark::RightShoulder};
constexpr Landmark kElbow[2] = {Landmark::LeftElbow, Landmark::RightElbow};
constexpr Landmark kWrist[2] = {Landmark::LeftWrist, Landmark::RightWrist};
constexpr Landmark kHand[2] = {Landmark::LeftHand, Landmark::RightHand};

double or_default(double v, double fallback) { return v > 0 ? v : fallback; }

// Unit vector of v with the component along unit axis a removed; nullopt when degenerate.
std::optional<Vec3> perpendicular_unit(const Vec3& v, const Vec3& a) {
  Vec3 p = v - v.dot(a) * a;
  const double n = p.norm();
  if (!(n > 1e-6)) return std::nullopt;
  return p / n;
}

class AnatomicalProfile {
 public:
  AnatomicalProfile(MarkerTrajectories& ms, const SubjectMeasurements& subject) : ms_(ms), subject_(subject) {
    for (int s = 0; s < 2; ++s)
      for (int r = 0; r < kSideRoleCount; ++r) side_[s][r] = match_role(ms_, kSideAliases[r], kSideLetter[s]);
    for (int r = 0; r < kCentralRoleCount; ++r) central_[r] = match_role(ms_, kCentralAliases[r], 0);
  }

  bool viable() const {
    const bool asis = side_[0][ASIS].marker >= 0 && side_[1][ASIS].marker >= 0;
    const bool hjc = side_[0][HJC].marker >= 0 && side_[1][HJC].marker >= 0;
    return asis || hjc;
  }
  std::string name() const {
    const std::string& a = side_[0][ASIS].alias;
    return a.find('_') != std::string::npos ? "cast" : "plug-in-gait";
  }

  MarkerLandmarks compute() {
    MarkerLandmarks out;
    out.profile = name();
    frames_ = ms_.num_frames;
    out.rigid_filled_samples = fill_segments();
    for (int s = 0; s < 2; ++s)
      for (int r = 0; r < kSideRoleCount; ++r) st_[s][r] = marker_track(ms_, side_[s][r].marker);
    for (int r = 0; r < kCentralRoleCount; ++r) ct_[r] = marker_track(ms_, central_[r].marker);

    Tracks& t = out.tracks;
    hips(out);
    if (ok(t[index(Landmark::LeftHip)]) && ok(t[index(Landmark::RightHip)])) {
      t[index(Landmark::Pelvis)] =
          mean_track(frames_, {&t[index(Landmark::LeftHip)], &t[index(Landmark::RightHip)]});
      add_method(out, Landmark::Pelvis, "midpoint of the hip joint centres");
    }
    for (int s = 0; s < 2; ++s) legs(out, s);
    trunk(out);
    for (int s = 0; s < 2; ++s) arms(out, s);
    return out;
  }

 private:
  const char* label(int s, SideRole r) const {
    return side_[s][r].marker >= 0 ? ms_.markers[static_cast<std::size_t>(side_[s][r].marker)].label.c_str() : "?";
  }
  const char* label(CentralRole r) const {
    return central_[r].marker >= 0 ? ms_.markers[static_cast<std::size_t>(central_[r].marker)].label.c_str() : "?";
  }
  double marker_radius() const { return 0.5 * or_default(subject_.marker_diameter_m, kDefaultMarkerDiameter); }

  int fill_segments() {
    int filled = 0;
    auto roles = [&](std::vector<int> extra, int s, std::initializer_list<SideRole> rs, std::initializer_list<CentralRole> cs) {
      for (SideRole r : rs)
        if (side_[s][r].marker >= 0) extra.push_back(side_[s][r].marker);
      for (CentralRole r : cs)
        if (central_[r].marker >= 0) extra.push_back(central_[r].marker);
      std::sort(extra.begin(), extra.end());
      extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
      return extra;
    };
    std::vector<std::vector<int>> segments;
    std::vector<int> pelvis = roles({}, 0, {ASIS, PSIS, HJC}, {SACR});
    pelvis = roles(pelvis, 1, {ASIS, PSIS, HJC}, {});
    segments.push_back(pelvis);
    std::vector<int> head = roles({}, 0, {FHD, BHD}, {HEAD});
    segments.push_back(roles(head, 1, {FHD, BHD}, {}));
    segments.push_back(roles({}, 0, {}, {C7, T10, CLAV, STRN}));
    for (int s = 0; s < 2; ++s) {
      const std::string l(1, kSideLetter[s]);
      segments.push_back(roles(numbered(ms_, {l + "TH", l + "THI", l + "_TH"}), s, {THI, KNE, KNM, KJC}, {}));
      segments.push_back(roles(numbered(ms_, {l + "TB", l + "SK", l + "SH", l + "TIB", l + "_TB"}), s, {TIB, ANK, MED, AJC}, {}));
      segments.push_back(roles({}, s, {HEE, TOE, MT1, MT5}, {}));
      segments.push_back(roles(numbered(ms_, {l + "UPA", l + "UA"}), s, {ELB, ELM, EJC}, {}));
      segments.push_back(roles(numbered(ms_, {l + "FRA", l + "FA"}), s, {WRA, WRB, WJC}, {}));
    }
    for (const auto& seg : segments) filled += fill_from_rigid_cluster(ms_, seg);
    return filled;
  }

  void hips(MarkerLandmarks& out) {
    Tracks& t = out.tracks;
    bool virtual_both = true;
    for (int s = 0; s < 2; ++s) virtual_both = virtual_both && ok(st_[s][HJC]);
    // Posterior pelvis point: PSIS midpoint, sacrum, or one PSIS (the depth is measured along
    // the pelvis x axis, so the lateral offset of a single PSIS does not matter).
    const Track* lasi = &st_[0][ASIS];
    const Track* rasi = &st_[1][ASIS];
    std::string posterior_names;
    if (ok(st_[0][PSIS]) && ok(st_[1][PSIS])) {
      posterior_ = mean_track(frames_, {&st_[0][PSIS], &st_[1][PSIS]});
      posterior_names = std::string(label(0, PSIS)) + " " + label(1, PSIS);
    } else if (ok(ct_[SACR])) {
      posterior_ = ct_[SACR];
      posterior_names = label(SACR);
    } else if (ok(st_[0][PSIS]) || ok(st_[1][PSIS])) {
      const int s = ok(st_[0][PSIS]) ? 0 : 1;
      posterior_ = st_[s][PSIS];
      posterior_names = label(s, PSIS);
    }
    const bool have_frame = ok(*lasi) && ok(*rasi) && ok(posterior_);
    if (have_frame) {
      // Subject constants: median pelvis width and depth over the trial.
      pelvis_width_ = median_over_frames(frames_, [&](int f) -> std::optional<double> {
                        if (!lasi->valid(f) || !rasi->valid(f) || !posterior_.valid(f)) return std::nullopt;
                        const auto pf = pelvis_frame(at(*lasi, f), at(*rasi, f), at(posterior_, f));
                        return pf ? std::optional<double>(pf->pelvis_width_m) : std::nullopt;
                      }).value_or(0);
      pelvis_depth_ = median_over_frames(frames_, [&](int f) -> std::optional<double> {
                        if (!lasi->valid(f) || !rasi->valid(f) || !posterior_.valid(f)) return std::nullopt;
                        const auto pf = pelvis_frame(at(*lasi, f), at(*rasi, f), at(posterior_, f));
                        return pf ? std::optional<double>(pf->pelvis_depth_m) : std::nullopt;
                      }).value_or(0);
      pelvis_y_ = build(frames_, {lasi, rasi, &posterior_}, [&](int f) -> std::optional<Vec3> {
        const auto pf = pelvis_frame(at(*lasi, f), at(*rasi, f), at(posterior_, f));
        if (!pf) return std::nullopt;
        return Vec3(pf->X_F_P.linear().col(1));
      });
    } else if (ok(*lasi) && ok(*rasi)) {
      pelvis_y_ = build(frames_, {lasi, rasi}, [&](int f) -> std::optional<Vec3> {
        const Vec3 y = at(*lasi, f) - at(*rasi, f);
        return y.norm() > 1e-4 ? std::optional<Vec3>(y.normalized()) : std::nullopt;
      });
    }
    for (int s = 0; s < 2; ++s) {
      const Landmark l = kHip[s];
      if (ok(st_[s][HJC])) {
        t[index(l)] = st_[s][HJC];
        add_method(out, l, std::string("virtual joint-centre marker ") + label(s, HJC));
        continue;
      }
      if (!have_frame || virtual_both || !(pelvis_width_ > 0) || !(pelvis_depth_ > 0)) continue;
      const bool left = s == 0;
      Vec3 local;
      std::string how;
      if (subject_.leg_length_m[s] > 0) {
        const double inter_asis = or_default(subject_.inter_asis_m, pelvis_width_);
        local = hip_centre_davis(subject_.leg_length_m[s], subject_.asis_trocanter_m[s], inter_asis, marker_radius(), left);
        how = format("Davis 1991 regression as in Plug-in Gait (leg length %.0f mm from the PROCESSING group)",
                     subject_.leg_length_m[s] * 1000);
      } else {
        local = hip_centre_harrington(pelvis_width_, pelvis_depth_, left);
        how = format("Harrington 2007 regression (pelvis width %.0f mm, depth %.0f mm)", pelvis_width_ * 1000,
                     pelvis_depth_ * 1000);
      }
      t[index(l)] = build(frames_, {lasi, rasi, &posterior_}, [&](int f) -> std::optional<Vec3> {
        const auto pf = pelvis_frame(at(*lasi, f), at(*rasi, f), at(posterior_, f));
        if (!pf) return std::nullopt;
        return pf->X_F_P * local;
      });
      add_method(out, l, how + " from " + label(0, ASIS) + " " + label(1, ASIS) + " " + posterior_names);
    }
  }

  // Lateral marker moved medially (perpendicular to the segment axis proximal->lateral) using
  // the pelvis' left axis for the medial direction.
  Track moved_medially(const Track& proximal, const Track& lateral, double offset, int s) {
    return build(frames_, {&proximal, &lateral, &pelvis_y_}, [&](int f) -> std::optional<Vec3> {
      const Vec3 axis = (at(lateral, f) - at(proximal, f)).normalized();
      const auto m = perpendicular_unit(-kSideSign[s] * at(pelvis_y_, f), axis);
      if (!m) return std::nullopt;
      return at(lateral, f) + offset * *m;
    });
  }

  void legs(MarkerLandmarks& out, int s) {
    Tracks& t = out.tracks;
    const Track& hjc = t[index(kHip[s])];
    const double md = or_default(subject_.marker_diameter_m, kDefaultMarkerDiameter);
    // Knee.
    const Landmark knee = kKnee[s];
    const double knee_offset = 0.5 * (or_default(subject_.knee_width_m[s], kDefaultKneeWidth) + md);
    if (ok(st_[s][KJC])) {
      t[index(knee)] = st_[s][KJC];
      add_method(out, knee, std::string("virtual joint-centre marker ") + label(s, KJC));
    } else if (ok(st_[s][KNE]) && ok(st_[s][KNM])) {
      t[index(knee)] = mean_track(frames_, {&st_[s][KNE], &st_[s][KNM]});
      add_method(out, knee, std::string("midpoint of ") + label(s, KNE) + " and " + label(s, KNM));
    } else if (ok(st_[s][KNE]) && ok(st_[s][THI]) && ok(hjc)) {
      const Track& kne = st_[s][KNE];
      const Track& thi = st_[s][THI];
      t[index(knee)] = build(frames_, {&hjc, &kne, &thi}, [&](int f) {
        return chord_joint_centre(at(hjc, f), at(kne, f), at(thi, f), knee_offset);
      });
      add_method(out, knee, format("Plug-in Gait chord function (hip centre, %s, %s, offset %.1f mm)", label(s, KNE),
                                   label(s, THI), knee_offset * 1000));
    } else if (ok(st_[s][KNE]) && ok(hjc) && ok(pelvis_y_)) {
      t[index(knee)] = moved_medially(hjc, st_[s][KNE], knee_offset, s);
      add_method(out, knee, format("%s moved %.1f mm medially", label(s, KNE), knee_offset * 1000));
    }
    // Ankle.
    const Landmark ankle = kAnkle[s];
    const Track& kjc = t[index(knee)];
    const double ankle_offset = 0.5 * (or_default(subject_.ankle_width_m[s], kDefaultAnkleWidth) + md);
    if (ok(st_[s][AJC])) {
      t[index(ankle)] = st_[s][AJC];
      add_method(out, ankle, std::string("virtual joint-centre marker ") + label(s, AJC));
    } else if (ok(st_[s][ANK]) && ok(st_[s][MED])) {
      t[index(ankle)] = mean_track(frames_, {&st_[s][ANK], &st_[s][MED]});
      add_method(out, ankle, std::string("midpoint of ") + label(s, ANK) + " and " + label(s, MED));
    } else if (ok(st_[s][ANK]) && ok(st_[s][TIB]) && ok(kjc)) {
      const Track& ank = st_[s][ANK];
      const Track& tib = st_[s][TIB];
      t[index(ankle)] = build(frames_, {&kjc, &ank, &tib}, [&](int f) {
        return chord_joint_centre(at(kjc, f), at(ank, f), at(tib, f), ankle_offset);
      });
      add_method(out, ankle, format("Plug-in Gait chord function (knee centre, %s, %s, offset %.1f mm)", label(s, ANK),
                                    label(s, TIB), ankle_offset * 1000));
    } else if (ok(st_[s][ANK]) && ok(kjc) && ok(pelvis_y_)) {
      t[index(ankle)] = moved_medially(kjc, st_[s][ANK], ankle_offset, s);
      add_method(out, ankle, format("%s moved %.1f mm medially", label(s, ANK), ankle_offset * 1000));
    }
    // Foot.
    if (ok(st_[s][TOE])) {
      t[index(kToe[s])] = st_[s][TOE];
      add_method(out, kToe[s], std::string("marker ") + label(s, TOE));
    } else if (ok(st_[s][MT1]) || ok(st_[s][MT5])) {
      t[index(kToe[s])] = mean_track(frames_, {&st_[s][MT1], &st_[s][MT5]});
      std::string names;
      for (SideRole r : {MT1, MT5})
        if (ok(st_[s][r])) names += std::string(names.empty() ? "" : " ") + label(s, r);
      add_method(out, kToe[s], "mean of the forefoot markers " + names);
    }
    if (ok(st_[s][HEE])) {
      t[index(kHeel[s])] = st_[s][HEE];
      add_method(out, kHeel[s], std::string("marker ") + label(s, HEE));
    }
  }

  void trunk(MarkerLandmarks& out) {
    Tracks& t = out.tracks;
    const Track& pelvis = t[index(Landmark::Pelvis)];
    // Head: centroid of the head markers.
    std::vector<const Track*> head;
    std::string head_names;
    for (int s = 0; s < 2; ++s)
      for (SideRole r : {FHD, BHD})
        if (ok(st_[s][r])) head.push_back(&st_[s][r]), head_names += std::string(" ") + label(s, r);
    if (ok(ct_[HEAD])) head.push_back(&ct_[HEAD]), head_names += std::string(" ") + label(HEAD);
    if (!head.empty()) {
      t[index(Landmark::Head)] = mean_track(frames_, head);
      add_method(out, Landmark::Head, "centroid of the head markers" + head_names);
    }
    // Neck: between C7 (back) and the jugular notch (front).
    if (ok(ct_[C7]) && ok(ct_[CLAV])) {
      t[index(Landmark::Neck)] = mean_track(frames_, {&ct_[C7], &ct_[CLAV]});
      add_method(out, Landmark::Neck, std::string("midpoint of ") + label(C7) + " and " + label(CLAV));
    }
    // Thorax up axis (Plug-in Gait: mid(C7, CLAV) - mid(T10, STRN)).
    if (ok(ct_[C7]) && ok(ct_[CLAV]) && ok(ct_[T10]) && ok(ct_[STRN])) {
      thorax_up_ = build(frames_, {&ct_[C7], &ct_[CLAV], &ct_[T10], &ct_[STRN]}, [&](int f) -> std::optional<Vec3> {
        const Vec3 up = at(ct_[C7], f) + at(ct_[CLAV], f) - at(ct_[T10], f) - at(ct_[STRN], f);
        return up.norm() > 1e-4 ? std::optional<Vec3>(up.normalized()) : std::nullopt;
      });
    } else if (ok(t[index(Landmark::Neck)]) && ok(pelvis)) {
      const Track& neck = t[index(Landmark::Neck)];
      thorax_up_ = build(frames_, {&neck, &pelvis}, [&](int f) -> std::optional<Vec3> {
        const Vec3 up = at(neck, f) - at(pelvis, f);
        return up.norm() > 1e-4 ? std::optional<Vec3>(up.normalized()) : std::nullopt;
      });
    }
    // Chest: centroid of the thorax markers, when both the front and the back are marked.
    std::vector<const Track*> thorax;
    std::string thorax_names;
    for (CentralRole r : {C7, CLAV, T10, STRN})
      if (ok(ct_[r])) thorax.push_back(&ct_[r]), thorax_names += std::string(" ") + label(r);
    const bool front = ok(ct_[CLAV]) || ok(ct_[STRN]);
    const bool back = ok(ct_[C7]) || ok(ct_[T10]);
    if (front && back && thorax.size() >= 3) {
      t[index(Landmark::Chest)] = mean_track(frames_, thorax);
      add_method(out, Landmark::Chest, "centroid of the thorax markers" + thorax_names);
    }
    // Spine (lumbar): halfway between the pelvis and the lower thorax.
    if (ok(pelvis) && ok(ct_[T10]) && ok(ct_[STRN])) {
      t[index(Landmark::Spine)] = build(frames_, {&pelvis, &ct_[T10], &ct_[STRN]}, [&](int f) -> std::optional<Vec3> {
        return 0.5 * at(pelvis, f) + 0.25 * (at(ct_[T10], f) + at(ct_[STRN], f));
      });
      add_method(out, Landmark::Spine, std::string("midpoint of the pelvis and mid(") + label(T10) + ", " + label(STRN) + ")");
    } else if (ok(pelvis) && ok(t[index(Landmark::Chest)])) {
      t[index(Landmark::Spine)] = mean_track(frames_, {&pelvis, &t[index(Landmark::Chest)]});
      add_method(out, Landmark::Spine, "midpoint of the pelvis and the chest");
    }
  }

  void arms(MarkerLandmarks& out, int s) {
    Tracks& t = out.tracks;
    const double md = or_default(subject_.marker_diameter_m, kDefaultMarkerDiameter);
    // Shoulder.
    const Landmark shoulder = kShoulder[s];
    const double shoulder_offset = or_default(subject_.shoulder_offset_m[s], kDefaultShoulderOffset) + 0.5 * md;
    if (ok(st_[s][SJC])) {
      t[index(shoulder)] = st_[s][SJC];
      add_method(out, shoulder, std::string("virtual joint-centre marker ") + label(s, SJC));
    } else if (ok(st_[s][SHO]) && ok(thorax_up_)) {
      const Track& sho = st_[s][SHO];
      t[index(shoulder)] = build(frames_, {&sho, &thorax_up_}, [&](int f) -> std::optional<Vec3> {
        return at(sho, f) - shoulder_offset * at(thorax_up_, f);
      });
      add_method(out, shoulder, format("%s moved %.1f mm down the thorax axis", label(s, SHO), shoulder_offset * 1000));
    }
    // Wrist.
    const Landmark wrist = kWrist[s];
    const Track& wra = st_[s][WRA];
    const Track& wrb = st_[s][WRB];
    if (ok(st_[s][WJC])) {
      t[index(wrist)] = st_[s][WJC];
      add_method(out, wrist, std::string("virtual joint-centre marker ") + label(s, WJC));
    } else if (ok(wra) && ok(wrb)) {
      const bool wrist_bar = side_[s][WRA].alias == expand("{S}WRA", kSideLetter[s]) &&
                             side_[s][WRB].alias == expand("{S}WRB", kSideLetter[s]);
      const Track& elb = st_[s][ELB];
      if (wrist_bar && ok(elb)) {
        // Plug-in Gait's wrist bar sits on the back of the wrist: move to mid-thickness. With
        // WRA on the thumb side, (WRA - WRB) x (elbow - wrist) points palmar for the left arm.
        const double offset = 0.5 * or_default(subject_.wrist_width_m[s], kDefaultWristThickness) + 0.5 * md;
        t[index(wrist)] = build(frames_, {&wra, &wrb, &elb}, [&](int f) -> std::optional<Vec3> {
          const Vec3 mid = 0.5 * (at(wra, f) + at(wrb, f));
          const Vec3 n = (at(wra, f) - at(wrb, f)).cross(at(elb, f) - mid);
          if (!(n.norm() > 1e-6)) return std::nullopt;
          return mid + kSideSign[s] * offset * n.normalized();
        });
        add_method(out, wrist, format("midpoint of %s and %s moved %.1f mm palmar (wrist bar)", label(s, WRA),
                                      label(s, WRB), offset * 1000));
      } else {
        t[index(wrist)] = mean_track(frames_, {&wra, &wrb});
        add_method(out, wrist, std::string("midpoint of ") + label(s, WRA) + " and " + label(s, WRB));
      }
    }
    // Elbow.
    const Landmark elbow = kElbow[s];
    const Track& elb = st_[s][ELB];
    const double elbow_offset = 0.5 * (or_default(subject_.elbow_width_m[s], kDefaultElbowWidth) + md);
    if (ok(st_[s][EJC])) {
      t[index(elbow)] = st_[s][EJC];
      add_method(out, elbow, std::string("virtual joint-centre marker ") + label(s, EJC));
    } else if (ok(elb) && ok(st_[s][ELM])) {
      t[index(elbow)] = mean_track(frames_, {&elb, &st_[s][ELM]});
      add_method(out, elbow, std::string("midpoint of ") + label(s, ELB) + " and " + label(s, ELM));
    } else if (ok(elb) && ok(t[index(shoulder)]) && (ok(wra) || ok(wrb) || ok(t[index(wrist)]))) {
      const Track& sjc = t[index(shoulder)];
      // The wrist markers' midpoint (what Plug-in Gait uses), else the wrist centre.
      const Track wrist_mid = (ok(wra) || ok(wrb)) ? mean_track(frames_, {&wra, &wrb}) : t[index(wrist)];
      t[index(elbow)] = build(frames_, {&sjc, &elb, &wrist_mid}, [&](int f) {
        return elbow_joint_centre(at(sjc, f), at(elb, f), at(wrist_mid, f), elbow_offset, s == 0);
      });
      add_method(out, elbow, format("Plug-in Gait elbow chord (shoulder centre, %s, wrist markers, offset %.1f mm)",
                                    label(s, ELB), elbow_offset * 1000));
    }
    // Hand.
    if (ok(st_[s][FIN]) || ok(st_[s][HM5])) {
      t[index(kHand[s])] = mean_track(frames_, {&st_[s][FIN], &st_[s][HM5]});
      std::string names;
      for (SideRole r : {FIN, HM5})
        if (ok(st_[s][r])) names += std::string(names.empty() ? "" : " ") + label(s, r);
      add_method(out, kHand[s], "mean of the hand markers " + names);
    }
  }

  MarkerTrajectories& ms_;
  const SubjectMeasurements& subject_;
  int frames_ = 0;
  RoleMatch side_[2][kSideRoleCount];
  RoleMatch central_[kCentralRoleCount];
  Track st_[2][kSideRoleCount];
  Track ct_[kCentralRoleCount];
  Track posterior_;
  Track pelvis_y_;
  Track thorax_up_;
  double pelvis_width_ = 0;
  double pelvis_depth_ = 0;
};

// ---- OptiTrack Arena / Motive "Skeleton" clusters ------------------------------------------------

class OptiTrackProfile {
 public:
  explicit OptiTrackProfile(MarkerTrajectories& ms) : ms_(ms) {
    for (std::size_t i = 0; i < ms_.markers.size(); ++i) {
      const std::string& n = ms_.markers[i].name;
      const auto us = n.rfind('_');
      std::string tail = us == std::string::npos ? n : n.substr(us + 1);
      std::size_t d = tail.size();
      while (d > 0 && tail[d - 1] >= '0' && tail[d - 1] <= '9') --d;
      if (d == tail.size() || d == 0) continue;
      const std::string segment = tail.substr(0, d);
      for (const char* known : {"HIP", "CHEST", "HEAD", "LSHOULDER", "RSHOULDER", "LUARM", "RUARM", "LHAND", "RHAND",
                                "LTHIGH", "RTHIGH", "LSHIN", "RSHIN", "LFOOT", "RFOOT"})
        if (segment == known) segments_[segment].push_back(static_cast<int>(i));
    }
  }

  bool viable() const {
    auto n = [&](const char* s) {
      auto it = segments_.find(s);
      return it == segments_.end() ? 0 : static_cast<int>(it->second.size());
    };
    return n("HIP") >= 3 && n("LTHIGH") >= 1 && n("RTHIGH") >= 1 && n("LSHIN") >= 1 && n("RSHIN") >= 1;
  }

  MarkerLandmarks compute() {
    MarkerLandmarks out;
    out.profile = "optitrack-skeleton";
    frames_ = ms_.num_frames;
    for (const char* s : {"HIP", "CHEST", "HEAD", "LHAND", "RHAND"}) out.rigid_filled_samples += fill_from_rigid_cluster(ms_, seg(s));
    Tracks& t = out.tracks;
    pelvis(out);
    for (int s = 0; s < 2; ++s) leg(out, s);
    if (ok(t[index(Landmark::LeftHip)]) && ok(t[index(Landmark::RightHip)])) {
      t[index(Landmark::Pelvis)] = mean_track(frames_, {&t[index(Landmark::LeftHip)], &t[index(Landmark::RightHip)]});
      add_method(out, Landmark::Pelvis, "midpoint of the hip joint centres");
    }
    upper(out);
    return out;
  }

 private:
  const std::vector<int>& seg(const std::string& name) const {
    static const std::vector<int> kNone;  // immutable empty list
    auto it = segments_.find(name);
    return it == segments_.end() ? kNone : it->second;
  }
  Track mean_of(const std::vector<int>& idx) const {
    std::vector<Track> ts;
    for (int i : idx) ts.push_back(marker_track(ms_, i));
    std::vector<const Track*> p;
    for (const Track& x : ts) p.push_back(&x);
    return mean_track(frames_, p);
  }
  std::string names(const std::vector<int>& idx) const {
    std::vector<std::string> n;
    for (int i : idx) n.push_back(ms_.markers[static_cast<std::size_t>(i)].label);
    return join(n, " ");
  }
  // Median over frames of the distance between marker i and a reference track.
  double median_distance(int i, const Track& ref) const {
    const MarkerTrajectory& m = ms_.markers[static_cast<std::size_t>(i)];
    return median_over_frames(frames_, [&](int f) -> std::optional<double> {
             if (!m.valid(f) || !ref.valid(f)) return std::nullopt;
             return (m.p_F.col(f) - at(ref, f)).norm();
           }).value_or(INFINITY);
  }
  // Marker of `candidates` whose median distance to `ref` is smallest (largest with `farthest`).
  int pick(const std::vector<int>& candidates, const Track& ref, bool farthest) const {
    int best = -1;
    double best_d = farthest ? -1 : INFINITY;
    for (int i : candidates) {
      const double d = median_distance(i, ref);
      if (!std::isfinite(d)) continue;
      if (farthest ? d > best_d : d < best_d) best = i, best_d = d;
    }
    return best;
  }

  void pelvis(MarkerLandmarks& out) {
    const std::vector<int>& hip = seg("HIP");
    const Track centroid = mean_of(hip);
    const Track thigh_l = mean_of(seg("LTHIGH"));
    const Track thigh_r = mean_of(seg("RTHIGH"));
    std::vector<int> upper_idx = seg("CHEST");
    if (upper_idx.empty()) upper_idx = seg("HEAD");
    const Track upper = mean_of(upper_idx);
    if (!ok(centroid) || !ok(thigh_l) || !ok(thigh_r) || !ok(upper)) return;
    // Average lateral and forward coordinates of each hip marker relative to the centroid.
    std::vector<double> lateral(hip.size(), 0.0), forward(hip.size(), 0.0);
    int n = 0;
    for (int f = 0; f < frames_; ++f) {
      if (!centroid.valid(f) || !thigh_l.valid(f) || !thigh_r.valid(f) || !upper.valid(f)) continue;
      bool all = true;
      for (int i : hip) all = all && ms_.markers[static_cast<std::size_t>(i)].valid(f);
      if (!all) continue;
      const Vec3 y = (at(thigh_l, f) - at(thigh_r, f)).normalized();
      const Vec3 up = (at(upper, f) - at(centroid, f)).normalized();
      const Vec3 x = y.cross(up);
      for (std::size_t k = 0; k < hip.size(); ++k) {
        const Vec3 d = ms_.markers[static_cast<std::size_t>(hip[k])].p_F.col(f) - at(centroid, f);
        lateral[k] += d.dot(y);
        forward[k] += d.dot(x);
      }
      ++n;
    }
    if (n == 0) return;
    const auto kl = static_cast<std::size_t>(std::max_element(lateral.begin(), lateral.end()) - lateral.begin());
    const auto kr = static_cast<std::size_t>(std::min_element(lateral.begin(), lateral.end()) - lateral.begin());
    if (kl == kr) return;
    left_ = marker_track(ms_, hip[kl]);
    right_ = marker_track(ms_, hip[kr]);
    std::vector<int> rest;
    std::vector<double> rest_forward;
    for (std::size_t k = 0; k < hip.size(); ++k)
      if (k != kl && k != kr) rest.push_back(hip[k]), rest_forward.push_back(forward[k]);
    if (rest.empty()) return;
    // AP direction: front minus back marker, or the single remaining marker's offset signed by
    // whether it lies in front.
    const auto kf = static_cast<std::size_t>(std::max_element(rest_forward.begin(), rest_forward.end()) - rest_forward.begin());
    const auto kb = static_cast<std::size_t>(std::min_element(rest_forward.begin(), rest_forward.end()) - rest_forward.begin());
    const Track front = marker_track(ms_, rest[kf]);
    const Track back = marker_track(ms_, rest[kb]);
    const double single_sign = rest_forward[kf] >= 0 ? 1.0 : -1.0;
    const bool pair = kf != kb;
    pelvis_x_ = build(frames_, {&left_, &right_, &front, &back}, [&](int f) -> std::optional<Vec3> {
      const Vec3 y = (at(left_, f) - at(right_, f)).normalized();
      const Vec3 ap = pair ? Vec3(at(front, f) - at(back, f))
                           : Vec3(single_sign * (at(front, f) - 0.5 * (at(left_, f) + at(right_, f))));
      return perpendicular_unit(ap, y);
    });
    width_ = median_over_frames(frames_, [&](int f) -> std::optional<double> {
               if (!left_.valid(f) || !right_.valid(f)) return std::nullopt;
               return (at(left_, f) - at(right_, f)).norm();
             }).value_or(0);
    if (!(width_ > 0.05)) return;
    for (int s = 0; s < 2; ++s) {
      const Vec3 local(0.0, kSideSign[s] * 0.25 * width_, -0.22 * width_);
      out.tracks[index(kHip[s])] = build(frames_, {&left_, &right_, &pelvis_x_}, [&](int f) -> std::optional<Vec3> {
        const Vec3 y = (at(left_, f) - at(right_, f)).normalized();
        const Vec3 x = at(pelvis_x_, f);
        Mat3 r;
        r.col(0) = x;
        r.col(1) = y;
        r.col(2) = x.cross(y);
        return Vec3(0.5 * (at(left_, f) + at(right_, f)) + r * local);
      });
      add_method(out, kHip[s],
                 format("waist markers %s/%s midpoint + (0, %+.0f, %.0f) mm in the pelvis cluster frame (anthropometric "
                        "approximation)",
                        ms_.markers[static_cast<std::size_t>(hip[kl])].label.c_str(),
                        ms_.markers[static_cast<std::size_t>(hip[kr])].label.c_str(), kSideSign[s] * 250 * width_,
                        -220 * width_));
    }
  }

  // Marker moved by `offset` medially, perpendicular to the segment axis.
  Track moved_medially(const Track& proximal, const Track& lateral, double offset, int s) {
    return build(frames_, {&proximal, &lateral, &left_, &right_}, [&](int f) -> std::optional<Vec3> {
      const Vec3 axis = (at(lateral, f) - at(proximal, f)).normalized();
      const Vec3 y = (at(left_, f) - at(right_, f)).normalized();
      const auto m = perpendicular_unit(-kSideSign[s] * y, axis);
      if (!m) return std::nullopt;
      return at(lateral, f) + offset * *m;
    });
  }

  void leg(MarkerLandmarks& out, int s) {
    Tracks& t = out.tracks;
    const std::string l(1, kSideLetter[s]);
    const Track& hjc = t[index(kHip[s])];
    const Track foot = mean_of(seg(l + "FOOT"));
    // The most distal marker of a segment (farthest from the proximal joint) is the one on the
    // lateral condyle / malleolus; the other is the cluster marker on the segment's front.
    const int knee_marker = ok(hjc) ? pick(seg(l + "THIGH"), hjc, true) : -1;
    if (knee_marker >= 0) {
      t[index(kKnee[s])] = moved_medially(hjc, marker_track(ms_, knee_marker), 0.057, s);
      add_method(out, kKnee[s], "lateral knee marker " + ms_.markers[static_cast<std::size_t>(knee_marker)].label +
                                    " (the thigh marker farthest from the hip) moved 57 mm medially");
    }
    const Track& kjc = t[index(kKnee[s])];
    const Track knee_lateral = knee_marker >= 0 ? marker_track(ms_, knee_marker) : Track{};
    const int ankle_marker = ok(knee_lateral) ? pick(seg(l + "SHIN"), knee_lateral, true) : -1;
    if (ankle_marker >= 0 && ok(kjc)) {
      t[index(kAnkle[s])] = moved_medially(kjc, marker_track(ms_, ankle_marker), 0.042, s);
      add_method(out, kAnkle[s], "lateral ankle marker " + ms_.markers[static_cast<std::size_t>(ankle_marker)].label +
                                     " (the shin marker farthest from the knee) moved 42 mm medially");
    }
    if (ok(foot)) {
      t[index(kToe[s])] = foot;
      add_method(out, kToe[s], "mean of the foot markers " + names(seg(l + "FOOT")));
    }
  }

  void upper(MarkerLandmarks& out) {
    Tracks& t = out.tracks;
    const Track& pelvis = t[index(Landmark::Pelvis)];
    if (!seg("HEAD").empty()) {
      t[index(Landmark::Head)] = mean_of(seg("HEAD"));
      add_method(out, Landmark::Head, "centroid of the head markers " + names(seg("HEAD")));
    }
    Track top[2];
    for (int s = 0; s < 2; ++s) {
      const int k = ok(pelvis) ? pick(seg(std::string(1, kSideLetter[s]) + "SHOULDER"), pelvis, true) : -1;
      if (k >= 0) top[s] = marker_track(ms_, k);
    }
    if (ok(top[0]) && ok(top[1])) {
      t[index(Landmark::Neck)] = mean_track(frames_, {&top[0], &top[1]});
      add_method(out, Landmark::Neck, "midpoint of the top shoulder markers");
      std::vector<Track> chest_tracks;
      for (int i : seg("CHEST")) chest_tracks.push_back(marker_track(ms_, i));
      std::vector<const Track*> chest{&top[0], &top[1]};
      for (const Track& c : chest_tracks) chest.push_back(&c);
      t[index(Landmark::Chest)] = mean_track(frames_, chest);
      add_method(out, Landmark::Chest, "centroid of the chest (back) markers and the top shoulder markers");
      if (ok(pelvis)) {
        t[index(Landmark::Spine)] = mean_track(frames_, {&pelvis, &t[index(Landmark::Chest)]});
        add_method(out, Landmark::Spine, "midpoint of the pelvis and the chest");
      }
    }
    const Track& neck = t[index(Landmark::Neck)];
    for (int s = 0; s < 2; ++s) {
      const std::string l(1, kSideLetter[s]);
      if (!ok(top[s]) || !ok(pelvis) || !ok(neck)) continue;
      t[index(kShoulder[s])] = build(frames_, {&top[s], &neck, &pelvis}, [&](int f) -> std::optional<Vec3> {
        const Vec3 up = at(neck, f) - at(pelvis, f);
        if (!(up.norm() > 1e-4)) return std::nullopt;
        return Vec3(at(top[s], f) - 0.057 * up.normalized());
      });
      add_method(out, kShoulder[s], "top shoulder marker moved 57 mm down the trunk axis");
      const Track& sjc = t[index(kShoulder[s])];
      const int elbow_marker = pick(seg(l + "UARM"), sjc, true);
      if (elbow_marker < 0) continue;
      const Track elb = marker_track(ms_, elbow_marker);
      std::vector<std::pair<double, int>> hand;
      for (int i : seg(l + "HAND")) {
        const double d = median_distance(i, elb);
        if (std::isfinite(d)) hand.emplace_back(d, i);
      }
      std::sort(hand.begin(), hand.end());
      if (hand.size() >= 2) {
        const Track a = marker_track(ms_, hand[0].second), b = marker_track(ms_, hand[1].second);
        t[index(kWrist[s])] = mean_track(frames_, {&a, &b});
        add_method(out, kWrist[s], "midpoint of the two hand markers nearest the elbow");
      }
      if (!hand.empty() && (hand.size() != 2)) {
        t[index(kHand[s])] = marker_track(ms_, hand.back().second);
        add_method(out, kHand[s], "hand marker " + ms_.markers[static_cast<std::size_t>(hand.back().second)].label);
      } else if (hand.size() == 2) {
        t[index(kHand[s])] = marker_track(ms_, hand[1].second);
        add_method(out, kHand[s], "hand marker " + ms_.markers[static_cast<std::size_t>(hand[1].second)].label);
      }
      const Track& wjc = t[index(kWrist[s])];
      if (ok(wjc)) {
        t[index(kElbow[s])] = build(frames_, {&sjc, &elb, &wjc}, [&](int f) -> std::optional<Vec3> {
          const Vec3 sw = at(wjc, f) - at(sjc, f);
          const double n2 = sw.squaredNorm();
          if (!(n2 > 1e-8)) return std::nullopt;
          const Vec3 e = at(elb, f);
          const Vec3 foot = at(sjc, f) + std::clamp((e - at(sjc, f)).dot(sw) / n2, 0.0, 1.0) * sw;
          const Vec3 d = foot - e;
          const double dn = d.norm();
          return dn > 1e-6 ? Vec3(e + std::min(0.045, dn) * d / dn) : e;
        });
        add_method(out, kElbow[s], "elbow marker " + ms_.markers[static_cast<std::size_t>(elbow_marker)].label +
                                       " moved 45 mm towards the shoulder-wrist line");
      }
    }
  }

  MarkerTrajectories& ms_;
  int frames_ = 0;
  std::map<std::string, std::vector<int>> segments_;
  Track left_, right_, pelvis_x_;
  double width_ = 0;
};

// ---- numbered segment clusters with functional joint centres --------------------------------------

class ClusterProfile {
 public:
  explicit ClusterProfile(MarkerTrajectories& ms) : ms_(ms) {
    pelvis_ = numbered(ms_, {"PV", "PEL", "PELVIS", "RPV", "LPV"});  // one rigid pelvis cluster, per side or not
    for (int s = 0; s < 2; ++s) {
      const std::string l(1, kSideLetter[s]);
      thigh_[s] = numbered(ms_, {l + "TH", l + "THI", l + "THIGH"});
      shank_[s] = numbered(ms_, {l + "SK", l + "SH", l + "TB", l + "TIB", l + "SHANK"});
      foot_[s] = numbered(ms_, {l + "FT", l + "FO", l + "FOOT"});
    }
  }
  bool viable() const { return pelvis_.size() >= 3 && thigh_[0].size() >= 3 && thigh_[1].size() >= 3; }

  MarkerLandmarks compute() {
    MarkerLandmarks out;
    out.profile = "segment-clusters";
    frames_ = ms_.num_frames;
    out.rigid_filled_samples += fill_from_rigid_cluster(ms_, pelvis_);
    for (int s = 0; s < 2; ++s)
      for (auto* c : {&thigh_[s], &shank_[s], &foot_[s]}) out.rigid_filled_samples += fill_from_rigid_cluster(ms_, *c);
    const ClusterPoses pelvis = track_cluster(ms_, pelvis_);
    Tracks& t = out.tracks;
    for (int s = 0; s < 2; ++s) {
      const ClusterPoses thigh = track_cluster(ms_, thigh_[s]);
      const ClusterPoses shank = shank_[s].size() >= 3 ? track_cluster(ms_, shank_[s]) : ClusterPoses{};
      const ClusterPoses foot = foot_[s].size() >= 3 ? track_cluster(ms_, foot_[s]) : ClusterPoses{};
      joint(out, kHip[s], pelvis, pelvis_, thigh, thigh_[s]);
      if (shank.reference_frame >= 0) joint(out, kKnee[s], thigh, thigh_[s], shank, shank_[s]);
      if (shank.reference_frame >= 0 && foot.reference_frame >= 0) joint(out, kAnkle[s], shank, shank_[s], foot, foot_[s]);
      // Toe: the foot marker farthest from the ankle centre.
      const Track& ajc = t[index(kAnkle[s])];
      if (ok(ajc) && !foot_[s].empty()) {
        int best = -1;
        double best_d = -1;
        for (int i : foot_[s]) {
          const MarkerTrajectory& m = ms_.markers[static_cast<std::size_t>(i)];
          const double d = median_over_frames(frames_, [&](int f) -> std::optional<double> {
                             if (!m.valid(f) || !ajc.valid(f)) return std::nullopt;
                             return (m.p_F.col(f) - at(ajc, f)).norm();
                           }).value_or(-1);
          if (d > best_d) best = i, best_d = d;
        }
        if (best >= 0) {
          t[index(kToe[s])] = marker_track(ms_, best);
          add_method(out, kToe[s], "foot marker " + ms_.markers[static_cast<std::size_t>(best)].label +
                                       " (the one farthest from the ankle centre)");
        }
      }
    }
    if (ok(t[index(Landmark::LeftHip)]) && ok(t[index(Landmark::RightHip)])) {
      t[index(Landmark::Pelvis)] = mean_track(frames_, {&t[index(Landmark::LeftHip)], &t[index(Landmark::RightHip)]});
      add_method(out, Landmark::Pelvis, "midpoint of the hip joint centres");
    }
    return out;
  }

 private:
  // Centroid of a cluster in its reference configuration.
  Vec3 reference_centroid(const ClusterPoses& c, const std::vector<int>& idx) const {
    Vec3 s = Vec3::Zero();
    int n = 0;
    for (int i : idx) {
      const MarkerTrajectory& m = ms_.markers[static_cast<std::size_t>(i)];
      if (m.state[static_cast<std::size_t>(c.reference_frame)] == SampleState::Measured) s += m.p_F.col(c.reference_frame), ++n;
    }
    return n ? Vec3(s / n) : Vec3::Zero();
  }

  void joint(MarkerLandmarks& out, Landmark l, const ClusterPoses& a, const std::vector<int>& ia, const ClusterPoses& b,
             const std::vector<int>& ib) {
    if (a.reference_frame < 0 || b.reference_frame < 0) return;
    for (const auto* c : {&a, &b}) {
      const auto& idx = c == &a ? ia : ib;
      if (c->valid_count() * 2 < frames_)
        out.warnings.push_back(format("cluster %s...: rigid fit in only %d of %d frames (markers missing, swapped or not "
                                      "rigid)", ms_.markers[static_cast<std::size_t>(idx[0])].label.c_str(),
                                      c->valid_count(), frames_));
    }
    // Prior: midway between the two cluster centroids, expressed in each reference configuration
    // (averaged over the frames where both clusters are tracked).
    const Vec3 ca = reference_centroid(a, ia), cb = reference_centroid(b, ib);
    Vec3 prior_a = Vec3::Zero(), prior_b = Vec3::Zero();
    int n = 0;
    for (std::size_t f = 0; f < a.valid.size() && f < b.valid.size(); ++f) {
      if (!a.valid[f] || !b.valid[f]) continue;
      const Vec3 mid = 0.5 * (a.X_F_S[f] * ca + b.X_F_S[f] * cb);
      prior_a += a.X_F_S[f].inverse() * mid;
      prior_b += b.X_F_S[f].inverse() * mid;
      ++n;
    }
    if (n == 0) return;
    const auto j = score_joint_centre(a, b, prior_a / n, prior_b / n);
    if (!j) {
      out.warnings.push_back(std::string(landmark_name(l)) + ": too few frames in which both clusters fit as rigid bodies");
      return;
    }
    Track& t = out.tracks[index(l)];
    t.present = true;
    t.p_W.setZero(3, frames_);
    t.state.assign(static_cast<std::size_t>(frames_), SampleState::Missing);
    for (int f = 0; f < frames_; ++f) {
      const auto k = static_cast<std::size_t>(f);
      if (!a.valid[k] || !b.valid[k]) continue;
      t.p_W.col(f) = 0.5 * (a.X_F_S[k] * j->c_a + b.X_F_S[k] * j->c_b);
      t.state[k] = SampleState::Measured;
    }
    add_method(out, l, format("functional joint centre (SCoRE) of clusters %s / %s over %d frames, rms %.1f mm",
                              ms_.markers[static_cast<std::size_t>(ia[0])].label.c_str(),
                              ms_.markers[static_cast<std::size_t>(ib[0])].label.c_str(), j->frames_used, j->rms_m * 1000));
  }

  MarkerTrajectories& ms_;
  int frames_ = 0;
  std::vector<int> pelvis_;
  std::vector<int> thigh_[2], shank_[2], foot_[2];
};

// ---- user marker map -----------------------------------------------------------------------------

void apply_marker_map(const MarkerMap& map, const MarkerTrajectories& ms, MarkerLandmarks& out) {
  for (const MarkerMapEntry& e : map.entries) {
    std::vector<Track> inputs;
    for (const std::string& name : e.markers) {
      int idx = -1;
      if (name.size() > 1 && name[0] == '#' && all_digits(std::string_view(name).substr(1)) && name.size() < 8) {
        const int point = std::stoi(name.substr(1)) - 1;
        for (std::size_t i = 0; i < ms.markers.size(); ++i)
          if (ms.markers[i].point_index == point) idx = static_cast<int>(i);
      } else {
        idx = ms.find(name);
      }
      if (idx < 0) {
        std::vector<std::string> some;
        for (std::size_t i = 0; i < ms.markers.size() && some.size() < 12; ++i)
          some.push_back(ms.markers[i].label.empty() ? "#" + std::to_string(ms.markers[i].point_index + 1)
                                                     : ms.markers[i].label);
        throw InputError(e.location, "marker '" + name + "' is not in the C3D file (it has " +
                                         std::to_string(ms.markers.size()) + " markers: " + join(some, ", ") +
                                         (ms.markers.size() > some.size() ? ", ..." : "") + ")");
      }
      inputs.push_back(marker_track(ms, idx));
    }
    std::vector<const Track*> p;
    for (const Track& t : inputs) p.push_back(&t);
    out.tracks[index(e.landmark)] = mean_track(ms.num_frames, p);
    auto& methods = out.methods;
    const std::string prefix = std::string(landmark_name(e.landmark)) + ": ";
    methods.erase(std::remove_if(methods.begin(), methods.end(), [&](const std::string& m) { return starts_with(m, prefix); }),
                  methods.end());
    add_method(out, e.landmark, (e.markers.size() == 1 ? "marker " : "mean of markers ") + join(e.markers, " ") +
                                    " (marker map " + map.name + ")");
  }
}

std::vector<Landmark> missing_landmarks(const MarkerLandmarks& ml) {
  std::vector<Landmark> out;
  for (Landmark l : all_landmarks())
    if (!ml.tracks[static_cast<std::size_t>(index(l))].present) out.push_back(l);
  return out;
}

[[noreturn]] void unrecognised(const MarkerTrajectories& ms, const std::string& location, const std::string& why,
                               const std::vector<Landmark>& missing) {
  int labelled = 0;
  std::vector<std::string> some;
  for (const MarkerTrajectory& m : ms.markers)
    if (!m.name.empty()) {
      ++labelled;
      if (some.size() < 8) some.push_back(m.label);
    }
  std::string what;
  if (ms.markers.empty()) what = "the file has no marker points";
  else if (labelled == 0) what = format("%zu markers, none labelled (no POINT:LABELS)", ms.markers.size());
  else what = format("%zu markers (%s%s)", ms.markers.size(), join(some, ", ").c_str(), labelled > 8 ? ", ..." : "");
  throw InputError(location, why + ": " + what + "; missing landmarks: " + landmark_list(missing) +
                                 "; give a marker map with --marker-map FILE.yaml (landmarks: {left_knee: [LKNE, LKNM], "
                                 "head: ['#1', '#2'], ...})");
}

}  // namespace

SubjectMeasurements subject_measurements(const c3d::C3dFile& file) {
  SubjectMeasurements s;
  auto get = [&](const char* name) -> double {
    const c3d::Parameter* p = file.find("PROCESSING", name);
    if (!p || p->numbers.empty() || !std::isfinite(p->numbers[0]) || p->numbers[0] <= 0) return 0.0;
    return p->numbers[0] * 0.001;  // Plug-in Gait writes millimetres
  };
  for (int k = 0; k < 2; ++k) {
    const std::string side = k == 0 ? "L" : "R";
    s.leg_length_m[k] = get((side + "LegLength").c_str());
    s.asis_trocanter_m[k] = get((side + "AsisTrocanterDistance").c_str());
    s.knee_width_m[k] = get((side + "KneeWidth").c_str());
    s.ankle_width_m[k] = get((side + "AnkleWidth").c_str());
    s.elbow_width_m[k] = get((side + "ElbowWidth").c_str());
    s.wrist_width_m[k] = get((side + "WristWidth").c_str());
    s.shoulder_offset_m[k] = get((side + "ShoulderOffset").c_str());
  }
  s.inter_asis_m = get("InterAsisDistance");
  s.marker_diameter_m = get("MarkerDiameter");
  // Implausible values (wrong units, typos) are ignored rather than trusted.
  for (double* v : {&s.leg_length_m[0], &s.leg_length_m[1]})
    if (*v < 0.4 || *v > 1.4) *v = 0;
  if (s.inter_asis_m < 0.1 || s.inter_asis_m > 0.45) s.inter_asis_m = 0;
  return s;
}

MarkerLandmarks compute_marker_landmarks(MarkerTrajectories& markers, const SubjectMeasurements& subject,
                                         const MarkerMap* map, const std::string& error_location) {
  MarkerLandmarks out;
  bool have_builtin = false;
  if (!map || map->start_from_builtin) {
    AnatomicalProfile anatomical(markers, subject);
    OptiTrackProfile optitrack(markers);
    ClusterProfile clusters(markers);
    if (anatomical.viable()) out = anatomical.compute(), have_builtin = true;
    else if (optitrack.viable()) out = optitrack.compute(), have_builtin = true;
    else if (clusters.viable()) out = clusters.compute(), have_builtin = true;
  }
  if (map) {
    apply_marker_map(*map, markers, out);
    out.profile = have_builtin ? out.profile + "+marker-map:" + map->name : "marker-map:" + map->name;
  }
  if (!have_builtin && !map)
    unrecognised(markers, error_location, "cannot recognise the marker set", missing_landmarks(out));
  // What retargeting needs at the least: the pelvis (or both hips) and a foot landmark for the floor.
  auto any_valid = [&](Landmark l) {
    const Track& t = out.tracks[static_cast<std::size_t>(index(l))];
    return t.present &&
           std::any_of(t.state.begin(), t.state.end(), [](SampleState s) { return s != SampleState::Missing; });
  };
  const bool pelvis = any_valid(Landmark::Pelvis) || (any_valid(Landmark::LeftHip) && any_valid(Landmark::RightHip));
  bool foot = false;
  for (Landmark l : {Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel, Landmark::RightAnkle, Landmark::RightToe,
                     Landmark::RightHeel})
    foot = foot || any_valid(l);
  if (!pelvis || !foot)
    unrecognised(markers, error_location,
                 std::string("the ") + out.profile + " markers give no " + (!pelvis ? "pelvis" : "foot") +
                     " landmark in any frame",
                 missing_landmarks(out));
  return out;
}

}  // namespace rt
