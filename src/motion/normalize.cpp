#include "retarget/motion/normalize.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/floor_plane.hpp"

namespace rt {

namespace {

constexpr Landmark kFootLandmarks[] = {Landmark::LeftAnkle, Landmark::LeftToe,  Landmark::LeftHeel,
                                       Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel};

// First frame at which both landmarks are valid, or -1.
int first_common_valid(const HumanMotion& m, Landmark a, Landmark b) {
  for (int f = 0; f < m.num_frames; ++f)
    if (m[a].valid(f) && m[b].valid(f)) return f;
  return -1;
}

// Rotation with the given x and y axes after Gram-Schmidt on (y, z_hint); returns false when the
// inputs are degenerate.
bool frame_from_y_and_up(const Vec3& y_axis, const Vec3& z_hint, Quat* out) {
  const double ny = y_axis.norm();
  if (!(ny > 1e-9)) return false;
  const Vec3 y = y_axis / ny;
  Vec3 z = z_hint - z_hint.dot(y) * y;
  const double nz = z.norm();
  if (!(nz > 1e-9)) return false;
  z /= nz;
  Mat3 R;
  R.col(0) = y.cross(z);
  R.col(1) = y;
  R.col(2) = z;
  *out = Quat(R).normalized();
  return true;
}

bool frame_from_x_and_up(const Vec3& x_axis, const Vec3& z_hint, Quat* out) {
  const double nx = x_axis.norm();
  if (!(nx > 1e-9)) return false;
  const Vec3 x = x_axis / nx;
  Vec3 z = z_hint - z_hint.dot(x) * x;
  const double nz = z.norm();
  if (!(nz > 1e-9)) return false;
  z /= nz;
  Mat3 R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  *out = Quat(R).normalized();
  return true;
}

// Fills `track.R_W` from a per-frame builder; frames where the builder fails copy the previous
// orientation (or the next good one at the start). Leaves has_orientation false if no frame works.
template <class Builder>
void fill_orientation(HumanMotion& m, Landmark target, Builder build) {
  LandmarkTrack& track = m[target];
  if (!track.present) return;
  std::vector<Quat> R(static_cast<std::size_t>(m.num_frames), Quat::Identity());
  std::vector<char> ok(static_cast<std::size_t>(m.num_frames), 0);
  int first_ok = -1;
  for (int f = 0; f < m.num_frames; ++f) {
    Quat q;
    if (build(f, &q)) {
      // Keep the quaternion hemisphere continuous so interpolation downstream never flips.
      if (first_ok >= 0 && q.coeffs().dot(R[static_cast<std::size_t>(f - 1)].coeffs()) < 0) q.coeffs() *= -1;
      R[static_cast<std::size_t>(f)] = q;
      ok[static_cast<std::size_t>(f)] = 1;
      if (first_ok < 0) first_ok = f;
    } else if (first_ok >= 0) {
      R[static_cast<std::size_t>(f)] = R[static_cast<std::size_t>(f - 1)];
    }
  }
  if (first_ok < 0) return;
  for (int f = 0; f < first_ok; ++f) R[static_cast<std::size_t>(f)] = R[static_cast<std::size_t>(first_ok)];
  track.R_W = std::move(R);
  track.has_orientation = true;
}

}  // namespace

Mat3 up_axis_to_z_up(char up_axis, bool negative) {
  Mat3 R;
  switch (up_axis) {
    case 'x': case 'X':  // (x, y, z) -> (y, z, x): a cyclic permutation, so still right-handed
      R << 0, 1, 0, 0, 0, 1, 1, 0, 0;
      break;
    case 'y': case 'Y':  // (x, y, z) -> (z, x, y)
      R << 0, 0, 1, 1, 0, 0, 0, 1, 0;
      break;
    case 'z': case 'Z':
      R.setIdentity();
      break;
    default:
      throw InputError(std::string("unknown up axis '") + up_axis + "' (expected x, y or z)");
  }
  if (negative) R = AngleAxis(M_PI, Vec3::UnitX()).toRotationMatrix() * R;  // flip z and y
  return R;
}

double estimate_floor_height(const HumanMotion& m, double percentile) {
  std::vector<double> lowest;
  lowest.reserve(static_cast<std::size_t>(m.num_frames));
  for (int f = 0; f < m.num_frames; ++f) {
    double z = INFINITY;
    for (Landmark l : kFootLandmarks)
      if (m[l].valid(f)) z = std::min(z, m[l].p_W(2, f));
    if (std::isfinite(z)) lowest.push_back(z);
  }
  if (lowest.empty())
    throw InputError(m.source.path, "cannot estimate the floor: no valid ankle, toe or heel landmark in any frame");
  const double p = std::clamp(percentile, 0.0, 1.0);
  const auto k = static_cast<std::size_t>(std::floor(p * static_cast<double>(lowest.size() - 1)));
  std::nth_element(lowest.begin(), lowest.begin() + static_cast<std::ptrdiff_t>(k), lowest.end());
  return lowest[k];
}

Iso3 start_alignment(const HumanMotion& m) {
  Landmark left = Landmark::LeftHip, right = Landmark::RightHip;
  int f = first_common_valid(m, left, right);
  if (f < 0) {
    left = Landmark::LeftShoulder;
    right = Landmark::RightShoulder;
    f = first_common_valid(m, left, right);
  }
  if (f < 0) return Iso3::Identity();
  const Vec3 lateral = m[left].p_W.col(f) - m[right].p_W.col(f);
  if (lateral.head<2>().norm() < 1e-6) return Iso3::Identity();
  const double yaw = M_PI / 2 - std::atan2(lateral.y(), lateral.x());
  Iso3 X = Iso3::Identity();
  X.linear() = AngleAxis(yaw, Vec3::UnitZ()).toRotationMatrix();
  Vec3 p_centre = 0.5 * (m[left].p_W.col(f) + m[right].p_W.col(f));
  if (m[Landmark::Pelvis].valid(f)) p_centre = m[Landmark::Pelvis].p_W.col(f);
  Vec3 shift = -(X.linear() * p_centre);
  shift.z() = 0;
  X.translation() = shift;
  return X;
}

void transform_motion(HumanMotion& m, const Iso3& X) {
  const Quat q(X.linear());
  for (LandmarkTrack& t : m.landmarks) {
    if (!t.present) continue;
    t.p_W = (X.linear() * t.p_W).colwise() + X.translation();
    if (t.has_orientation)
      for (Quat& r : t.R_W) r = (q * r).normalized();
  }
}

void derive_orientations(HumanMotion& m) {
  auto valid = [&](Landmark l, int f) { return m[l].valid(f); };
  auto p = [&](Landmark l, int f) -> Vec3 { return m[l].p_W.col(f); };
  auto first_valid = [&](int f, std::initializer_list<Landmark> ls, Landmark* out) {
    for (Landmark l : ls)
      if (valid(l, f)) {
        *out = l;
        return true;
      }
    return false;
  };

  fill_orientation(m, Landmark::Pelvis, [&](int f, Quat* q) {
    if (!valid(Landmark::LeftHip, f) || !valid(Landmark::RightHip, f) || !valid(Landmark::Pelvis, f)) return false;
    Landmark upper;
    Vec3 up = Vec3::UnitZ();
    if (first_valid(f, {Landmark::Spine, Landmark::Chest, Landmark::Neck}, &upper)) up = p(upper, f) - p(Landmark::Pelvis, f);
    return frame_from_y_and_up(p(Landmark::LeftHip, f) - p(Landmark::RightHip, f), up, q);
  });

  fill_orientation(m, Landmark::Chest, [&](int f, Quat* q) {
    if (!valid(Landmark::LeftShoulder, f) || !valid(Landmark::RightShoulder, f) || !valid(Landmark::Chest, f)) return false;
    Landmark upper, lower;
    Vec3 up = Vec3::UnitZ();
    if (first_valid(f, {Landmark::Neck, Landmark::Head}, &upper) &&
        first_valid(f, {Landmark::Spine, Landmark::Pelvis}, &lower))
      up = p(upper, f) - p(lower, f);
    return frame_from_y_and_up(p(Landmark::LeftShoulder, f) - p(Landmark::RightShoulder, f), up, q);
  });

  for (auto [ankle, toe, heel] : {std::array<Landmark, 3>{Landmark::LeftAnkle, Landmark::LeftToe, Landmark::LeftHeel},
                                  std::array<Landmark, 3>{Landmark::RightAnkle, Landmark::RightToe, Landmark::RightHeel}}) {
    if (!m[toe].present) continue;
    if (m[heel].present) {
      fill_orientation(m, ankle, [&, ankle = ankle, toe = toe, heel = heel](int f, Quat* q) {
        if (!valid(ankle, f) || !valid(toe, f) || !valid(heel, f)) return false;
        // Sole direction heel -> toe; the ankle above the heel-toe line fixes the sagittal plane.
        const Vec3 x = p(toe, f) - p(heel, f);
        const Vec3 y = (p(ankle, f) - p(heel, f)).cross(x);
        return frame_from_x_and_up(x, x.cross(y), q);
      });
      continue;
    }
    // Without a heel the foot axis is ankle -> toe, which slopes down by the (unknown) height of
    // the ankle over the ball, and the roll is unobservable (assumed zero). The slope is removed
    // with a constant pitch: the median slope over the frames where the toe is on the floor.
    // The heading comes from the plane of the shank and the foot axis (its normal, levelled, is the
    // foot's y axis): with the world vertical instead, a foot pointing its toes down in swing (the
    // ankle-toe axis vertical) has no heading and the frame flips by 180° between frames.
    const Landmark knee = ankle == Landmark::LeftAnkle ? Landmark::LeftKnee : Landmark::RightKnee;
    fill_orientation(m, ankle, [&, ankle = ankle, toe = toe, knee](int f, Quat* q) {
      if (!valid(ankle, f) || !valid(toe, f)) return false;
      const Vec3 axis = p(toe, f) - p(ankle, f);
      if (valid(knee, f)) {
        const Vec3 shank = p(knee, f) - p(ankle, f);
        Vec3 y = shank.cross(axis);
        y.z() = 0;  // levelled: zero roll
        // The plane is defined while the foot axis and the shank are more than ~15° apart.
        if (y.norm() > 0.25 * shank.norm() * axis.norm()) return frame_from_x_and_up(axis, axis.cross(y.normalized()), q);
      }
      return frame_from_x_and_up(axis, Vec3::UnitZ(), q);
    });
    LandmarkTrack& t = m[ankle];
    if (!t.has_orientation) continue;
    double toe_floor = INFINITY;
    for (int f = 0; f < m.num_frames; ++f)
      if (valid(toe, f)) toe_floor = std::min(toe_floor, p(toe, f).z());
    std::vector<double> slopes;
    for (int f = 0; f < m.num_frames; ++f) {
      if (!valid(toe, f) || !valid(ankle, f) || p(toe, f).z() > toe_floor + 0.02) continue;
      const Vec3 x = t.R_W[static_cast<std::size_t>(f)] * Vec3::UnitX();
      slopes.push_back(std::asin(std::clamp(-x.z(), -1.0, 1.0)));
    }
    if (slopes.empty()) continue;
    std::nth_element(slopes.begin(), slopes.begin() + static_cast<std::ptrdiff_t>(slopes.size() / 2), slopes.end());
    const Quat level(AngleAxis(-slopes[slopes.size() / 2], Vec3::UnitY()));
    for (Quat& r : t.R_W) r = (r * level).normalized();
  }
}

void normalize_motion(HumanMotion& m, const NormalizeOptions& options) {
  const double floor = estimate_floor_height(m, options.floor_percentile);
  m.source.floor_height_m = floor;
  if (options.move_floor_to_zero) {
    Iso3 shift = Iso3::Identity();
    shift.translation().z() = -floor;
    transform_motion(m, shift);
  }
  if (options.align_start) transform_motion(m, start_alignment(m));
  if (options.level_floor && options.move_floor_to_zero) {
    // A tilted floor (or a tilted capture volume) is levelled, then moved to z = 0 again.
    const FloorPlane plane = estimate_floor_plane(m);
    m.source.floor_unevenness_m = plane.unevenness_m;
    if (plane.rejected_steep)
      m.diagnostics.warn(m.source.path, format("floor: the feet's contacts fit a plane steeper than %g deg; not levelled",
                                               FloorPlaneOptions{}.max_tilt_deg));
    if (plane.tilt_deg > options.level_min_tilt_deg) {
      level_onto_floor(m, plane);
      m.source.floor_tilt_deg = plane.tilt_deg;
      Iso3 shift = Iso3::Identity();
      shift.translation().z() = -estimate_floor_height(m, options.floor_percentile);
      transform_motion(m, shift);
      if (plane.tilt_deg > options.warn_tilt_deg)
        m.diagnostics.warn(m.source.path, format("floor: tilted %.2f deg under the feet's contacts; the motion was levelled onto z = 0",
                                                 plane.tilt_deg));
    }
    if (plane.unevenness_m > options.warn_unevenness_m)
      m.diagnostics.warn(m.source.path, format("floor: uneven, the feet's contact heights spread %.1f cm about a plane "
                                               "(steps, a ramp or marker drift); robot stance soles are put on one level floor",
                                               100 * plane.unevenness_m));
  }
  derive_orientations(m);
}

}  // namespace rt
