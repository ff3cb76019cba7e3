#include "retarget/motion/asf/asf_motion.hpp"

#include <cmath>
#include <filesystem>

#include "retarget/core/error.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"

namespace rt {

namespace fs = std::filesystem;

namespace {

constexpr double kCmuFps = 120.0;

Mat3 axis_rotation(int axis, double angle_rad) {
  return AngleAxis(angle_rad, Vec3::Unit(axis)).toRotationMatrix();
}

// Rotations about fixed axes applied in `order` (order[0] first): R = R_o2 R_o1 R_o0.
Mat3 ordered_rotation(const std::array<int, 3>& order, const Vec3& angles_rad) {
  Mat3 R = Mat3::Identity();
  for (int k = 0; k < 3; ++k) R = axis_rotation(order[k], angles_rad[order[k]]) * R;
  return R;
}

// R = Rz(z) Ry(y) Rx(x) [degrees] (the BVH channels "Zrotation Yrotation Xrotation").
Vec3 zyx_degrees(const Mat3& R) {
  const double sy = std::clamp(-R(2, 0), -1.0, 1.0);
  const double y = std::asin(sy);
  double z = 0, x = 0;
  if (std::abs(sy) < 1 - 1e-12) {
    z = std::atan2(R(1, 0), R(0, 0));
    x = std::atan2(R(2, 1), R(2, 2));
  } else {
    x = std::atan2(-R(1, 2), R(1, 1));  // gimbal lock: z = 0 carries the whole rotation about the vertical
  }
  const double deg = 180.0 / M_PI;
  return Vec3(z * deg, y * deg, x * deg);
}

}  // namespace

std::string find_asf_for(const std::string& amc_path, const std::string& options_asf) {
  if (!options_asf.empty()) {
    std::error_code ec;
    if (!fs::is_regular_file(options_asf, ec)) throw InputError(options_asf, "--asf: no such file");
    return options_asf;
  }
  const fs::path amc(amc_path);
  const fs::path dir = amc.parent_path();
  const std::string stem = amc.stem().string();
  std::vector<fs::path> candidates;
  if (const auto underscore = stem.find('_'); underscore != std::string::npos && underscore > 0)
    candidates.push_back(dir / (stem.substr(0, underscore) + ".asf"));  // CMU: 01_01.amc -> 01.asf
  candidates.push_back(dir / (stem + ".asf"));
  for (const fs::path& c : candidates)
    for (const char* ext : {".asf", ".ASF"}) {
      fs::path p = c;
      p.replace_extension(ext);
      std::error_code ec;
      if (fs::is_regular_file(p, ec)) return p.string();
    }
  std::vector<fs::path> in_dir;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec))
    if (e.is_regular_file(ec) && to_lower(e.path().extension().string()) == ".asf") in_dir.push_back(e.path());
  if (in_dir.size() == 1) return in_dir.front().string();
  std::vector<std::string> names;
  for (const fs::path& c : candidates) names.push_back(c.filename().string());
  throw InputError(amc_path, "no skeleton for this AMC: expected " + join(names, " or ") +
                                 " beside it (CMU naming), or give the ASF with --asf FILE");
}

BvhFile asf_amc_to_bvh(const AsfSkeleton& s, const AmcMotion& m, double frame_time_s, const std::string& name) {
  const bool amc_degrees = m.has_angle_unit ? m.angles_in_degrees : s.angles_in_degrees;
  const double amc_rad = amc_degrees ? M_PI / 180.0 : 1.0;
  const double asf_rad = s.angles_in_degrees ? M_PI / 180.0 : 1.0;
  BvhFile f;
  f.name = name;
  f.num_frames = m.num_frames;
  f.declared_frames = m.num_frames;
  f.frame_time_s = frame_time_s;
  const std::size_t B = s.bones.size();
  // Joint 0 the root, joint 1 + b bone b (parents precede children in the ASF bone order).
  BvhJoint root;
  root.name = "root";
  root.offset = s.root_position;
  root.channels = {BvhChannel::Xposition, BvhChannel::Yposition, BvhChannel::Zposition,
                   BvhChannel::Zrotation, BvhChannel::Yrotation, BvhChannel::Xrotation};
  f.joints.push_back(root);
  std::vector<Mat3> C(B), C_inv(B);
  for (std::size_t b = 0; b < B; ++b) {
    const AsfBone& bone = s.bones[b];
    C[b] = ordered_rotation(bone.axis_order, bone.axis_angles * asf_rad);
    C_inv[b] = C[b].transpose();
    BvhJoint j;
    j.name = bone.name;
    j.parent = bone.parent < 0 ? 0 : bone.parent + 1;
    j.line = bone.line;
    // The bone starts at its parent's end: the parent bone's vector in the parent's rest frame.
    if (bone.parent >= 0) {
      const AsfBone& parent = s.bones[static_cast<std::size_t>(bone.parent)];
      j.offset = parent.length * parent.direction;
    }
    if (!bone.dofs.empty()) j.channels = {BvhChannel::Zrotation, BvhChannel::Yrotation, BvhChannel::Xrotation};
    f.joints.push_back(j);
  }
  std::vector<char> has_child(B, 0);
  for (const AsfBone& bone : s.bones)
    if (bone.parent >= 0) has_child[static_cast<std::size_t>(bone.parent)] = 1;
  for (std::size_t b = 0; b < B; ++b)
    if (!has_child[b]) f.end_sites.push_back({static_cast<int>(b) + 1, s.bones[b].length * s.bones[b].direction, s.bones[b].line});
  int column = 0;
  for (BvhJoint& j : f.joints) {
    j.first_column = column;
    column += static_cast<int>(j.channels.size());
  }
  f.num_channels = column;
  f.values.assign(static_cast<std::size_t>(f.num_frames) * static_cast<std::size_t>(f.num_channels), 0.0);

  const Mat3 C_root = ordered_rotation(s.root_axis_order, s.root_orientation * asf_rad);
  for (int t = 0; t < m.num_frames; ++t) {
    const double* in = m.frame(t);
    double* out = f.values.data() + static_cast<std::size_t>(t) * static_cast<std::size_t>(f.num_channels);
    Vec3 position = Vec3::Zero(), angles = Vec3::Zero();
    for (std::size_t k = 0; k < s.root_order.size(); ++k) {
      const AsfDof& d = s.root_order[k];
      (d.rotation ? angles : position)[d.axis] = d.rotation ? in[k] * amc_rad : in[k];
    }
    // The root rotations in the root's axis order (those the order does not list are 0).
    const Mat3 root_R = C_root * ordered_rotation(s.root_axis_order, angles) * C_root.transpose();
    const Vec3 zyx = zyx_degrees(root_R);
    for (int i = 0; i < 3; ++i) out[i] = s.root_position[i] + position[i];
    for (int i = 0; i < 3; ++i) out[3 + i] = zyx[i];
    for (std::size_t b = 0; b < B; ++b) {
      const AsfBone& bone = s.bones[b];
      if (bone.dofs.empty()) continue;
      Mat3 M = Mat3::Identity();
      const double* v = in + m.bone_column[b];
      for (std::size_t k = 0; k < bone.dofs.size(); ++k) M = axis_rotation(bone.dofs[k].axis, v[k] * amc_rad) * M;
      const Vec3 local = zyx_degrees(C[b] * M * C_inv[b]);
      double* o = out + f.joints[b + 1].first_column;
      for (int i = 0; i < 3; ++i) o[i] = local[i];
    }
  }
  return f;
}

HumanMotion load_asf_amc_motion(const std::string& amc_path, const MotionLoadOptions& options) {
  const std::string asf_path = find_asf_for(amc_path, options.asf_path);
  const AsfSkeleton skeleton = read_asf(asf_path);
  const AmcMotion motion = read_amc(amc_path, skeleton);
  const BvhFile bvh = asf_amc_to_bvh(skeleton, motion, 1.0 / kCmuFps, amc_path);
  HumanMotion m = bvh_to_human_motion(bvh, options);
  m.source.format = "asf/amc";
  m.source.details["asf"] = asf_path;
  m.source.details["bones"] = std::to_string(skeleton.bones.size());
  if (!options.source_fps)
    m.diagnostics.note(amc_path, "AMC files state no frame rate: 120 Hz (the CMU library's) assumed; override with --source-fps");
  m.diagnostics.note(amc_path, "skeleton from " + base_name(asf_path));
  return m;
}

}  // namespace rt
