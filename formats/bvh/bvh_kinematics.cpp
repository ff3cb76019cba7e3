#include "formats/bvh/bvh_kinematics.hpp"

#include <cmath>

#include "retarget/core/error.hpp"

namespace rt {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// R <- R * R_axis(angle): an intrinsic rotation changes only the two columns orthogonal to the
// axis, which is cheaper than a full 3x3 product and is the hot loop of BVH loading.
inline void rotate_intrinsic(Mat3& R, int axis, double angle_deg) {
  const double a = angle_deg * kDegToRad;
  const double c = std::cos(a), s = std::sin(a);
  const int i = (axis + 1) % 3, k = (axis + 2) % 3;  // X: (y, z), Y: (z, x), Z: (x, y)
  const Vec3 ci = R.col(i), ck = R.col(k);
  R.col(i) = c * ci + s * ck;
  R.col(k) = c * ck - s * ci;
}

}  // namespace

Mat3 bvh_local_rotation(const BvhJoint& joint, const double* frame_values) {
  Mat3 R = Mat3::Identity();
  const double* v = frame_values + joint.first_column;
  for (std::size_t k = 0; k < joint.channels.size(); ++k)
    if (bvh_is_rotation(joint.channels[k])) rotate_intrinsic(R, bvh_channel_axis(joint.channels[k]), v[k]);
  return R;
}

Vec3 bvh_local_translation(const BvhJoint& joint, const double* frame_values) {
  Vec3 t = joint.offset;
  const double* v = frame_values + joint.first_column;
  for (std::size_t k = 0; k < joint.channels.size(); ++k)
    if (!bvh_is_rotation(joint.channels[k])) t[bvh_channel_axis(joint.channels[k])] = v[k];
  return t;
}

void bvh_forward_kinematics(const BvhFile& file, int frame, BvhPose& pose, const std::vector<char>* joint_mask) {
  RT_DEMAND(frame >= 0 && frame < file.num_frames, "BVH frame index out of range");
  const auto n = static_cast<Eigen::Index>(file.joints.size());
  if (pose.p_F_joint.cols() != n) {
    pose.R_F_joint.assign(file.joints.size(), Mat3::Identity());
    pose.p_F_joint.setZero(3, n);
  }
  if (pose.p_F_end_site.cols() != static_cast<Eigen::Index>(file.end_sites.size()))
    pose.p_F_end_site.setZero(3, static_cast<Eigen::Index>(file.end_sites.size()));
  RT_DEMAND(!joint_mask || joint_mask->size() == file.joints.size(), "BVH joint mask size mismatch");

  const double* values = file.frame(frame);
  for (std::size_t j = 0; j < file.joints.size(); ++j) {
    if (joint_mask && !(*joint_mask)[j]) continue;
    const BvhJoint& joint = file.joints[j];
    Vec3 t = joint.offset;
    Mat3 R;
    Vec3 p;
    if (joint.parent >= 0) {
      R = pose.R_F_joint[static_cast<std::size_t>(joint.parent)];
      p = pose.p_F_joint.col(joint.parent);
    } else {
      R.setIdentity();
      p.setZero();
    }
    const Mat3 R_parent = R;
    const double* v = values + joint.first_column;
    for (std::size_t k = 0; k < joint.channels.size(); ++k) {
      const BvhChannel ch = joint.channels[k];
      if (bvh_is_rotation(ch)) rotate_intrinsic(R, bvh_channel_axis(ch), v[k]);
      else t[bvh_channel_axis(ch)] = v[k];
    }
    pose.p_F_joint.col(static_cast<Eigen::Index>(j)) = p + R_parent * t;
    pose.R_F_joint[j] = R;
  }
  for (std::size_t e = 0; e < file.end_sites.size(); ++e) {
    const BvhEndSite& site = file.end_sites[e];
    if (joint_mask && !(*joint_mask)[static_cast<std::size_t>(site.parent)]) continue;
    pose.p_F_end_site.col(static_cast<Eigen::Index>(e)) =
        pose.p_F_joint.col(site.parent) + pose.R_F_joint[static_cast<std::size_t>(site.parent)] * site.offset;
  }
}

std::vector<char> bvh_ancestor_closure(const BvhFile& file, const std::vector<int>& joints) {
  std::vector<char> mask(file.joints.size(), 0);
  for (int j : joints) {
    // Parents precede children (BvhFile invariant), so the walk ends; the bound guards it anyway.
    for (std::size_t steps = 0; j >= 0 && j < static_cast<int>(file.joints.size()) && steps <= file.joints.size(); ++steps) {
      if (mask[static_cast<std::size_t>(j)]) break;
      mask[static_cast<std::size_t>(j)] = 1;
      j = file.joints[static_cast<std::size_t>(j)].parent;
    }
  }
  return mask;
}

}  // namespace rt
