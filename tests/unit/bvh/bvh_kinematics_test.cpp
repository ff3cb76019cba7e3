// Forward kinematics of BVH skeletons: hand-computed cases, Euler-order composition against Eigen,
// and global joint positions against assimp's BVH importer (an independent implementation) on
// every real clip.

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <random>

#include "formats/bvh/bvh_kinematics.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

constexpr double kDeg = M_PI / 180.0;

const char* kTwoJoints = R"(HIERARCHY
ROOT Root
{
 OFFSET 100 100 100
 CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
 JOINT Child
 {
  OFFSET 0 10 0
  CHANNELS 3 Xrotation Yrotation Zrotation
  End Site
  {
   OFFSET 0 5 0
  }
 }
}
MOTION
Frames: 2
Frame Time: 0.1
1 2 3 90 0 0 90 0 0
0 0 0 0 90 0 0 0 90
)";

TEST(BvhKinematics, HandComputedTwoJointChain) {
  const BvhFile f = parse_bvh(kTwoJoints, "two.bvh");
  BvhPose pose;
  // Frame 0: root at (1, 2, 3) (position channels replace the root OFFSET), R_root = Rz(90):
  // child = (1, 2, 3) + Rz90 (0, 10, 0) = (-9, 2, 3); R_child = Rz90 Rx90, so the End Site is
  // child + Rz90 Rx90 (0, 5, 0) = child + Rz90 (0, 0, 5) = (-9, 2, 8).
  bvh_forward_kinematics(f, 0, pose);
  EXPECT_TRUE(pose.p_F_joint.col(0).isApprox(Vec3(1, 2, 3), 1e-12));
  EXPECT_LT((pose.p_F_joint.col(1) - Vec3(-9, 2, 3)).norm(), 1e-12);
  EXPECT_LT((pose.p_F_end_site.col(0) - Vec3(-9, 2, 8)).norm(), 1e-12);
  // Frame 1: root at the origin with Xrotation 90 (channel 5 of the root is Xrotation):
  // child = Rx90 (0, 10, 0) = (0, 0, 10); child Zrotation 90: End Site = child + Rx90 Rz90 (0, 5, 0)
  // = child + Rx90 (-5, 0, 0) = (-5, 0, 10).
  bvh_forward_kinematics(f, 1, pose);
  EXPECT_LT((pose.p_F_joint.col(1) - Vec3(0, 0, 10)).norm(), 1e-12);
  EXPECT_LT((pose.p_F_end_site.col(0) - Vec3(-5, 0, 10)).norm(), 1e-12);
}

TEST(BvhKinematics, RotationOrderIsIntrinsicInDeclaredOrder) {
  // Z=90 then X=90 maps the child offset (0, 1, 0) to (0, 0, 1); X=90 then Z=90 maps it to (-1, 0, 0).
  const std::string zx = R"(HIERARCHY
ROOT A
{
 OFFSET 0 0 0
 CHANNELS 2 Zrotation Xrotation
 JOINT B
 {
  OFFSET 0 1 0
  CHANNELS 0
 }
}
MOTION
Frames: 1
Frame Time: 1
90 90
)";
  std::string xz = zx;
  xz.replace(xz.find("Zrotation Xrotation"), 19, "Xrotation Zrotation");
  BvhPose pose;
  bvh_forward_kinematics(parse_bvh(zx, "zx.bvh"), 0, pose);
  EXPECT_LT((pose.p_F_joint.col(1) - Vec3(0, 0, 1)).norm(), 1e-12);
  bvh_forward_kinematics(parse_bvh(xz, "xz.bvh"), 0, pose);
  EXPECT_LT((pose.p_F_joint.col(1) - Vec3(-1, 0, 0)).norm(), 1e-12);
}

TEST(BvhKinematics, LocalRotationMatchesEigenForEveryOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-180, 180);
  const std::vector<std::vector<BvhChannel>> orders = {
      {BvhChannel::Xrotation, BvhChannel::Yrotation, BvhChannel::Zrotation},
      {BvhChannel::Xrotation, BvhChannel::Zrotation, BvhChannel::Yrotation},
      {BvhChannel::Yrotation, BvhChannel::Xrotation, BvhChannel::Zrotation},
      {BvhChannel::Yrotation, BvhChannel::Zrotation, BvhChannel::Xrotation},
      {BvhChannel::Zrotation, BvhChannel::Xrotation, BvhChannel::Yrotation},
      {BvhChannel::Zrotation, BvhChannel::Yrotation, BvhChannel::Xrotation},
      {BvhChannel::Xposition, BvhChannel::Yrotation, BvhChannel::Zposition, BvhChannel::Xrotation},
      {BvhChannel::Zrotation}};
  for (const auto& order : orders) {
    for (int trial = 0; trial < 20; ++trial) {
      BvhJoint j;
      j.channels = order;
      j.first_column = 2;
      std::vector<double> values(order.size() + 2, 0.0);
      Mat3 expected = Mat3::Identity();
      for (std::size_t k = 0; k < order.size(); ++k) {
        values[k + 2] = angle(rng);
        if (bvh_is_rotation(order[k]))
          expected = expected * AngleAxis(values[k + 2] * kDeg, Vec3::Unit(bvh_channel_axis(order[k]))).toRotationMatrix();
      }
      EXPECT_LT((bvh_local_rotation(j, values.data()) - expected).norm(), 1e-12);
    }
  }
}

TEST(BvhKinematics, PositionChannelsReplaceTheOffsetComponentwise) {
  BvhJoint j;
  j.offset = Vec3(1, 10, 100);
  j.channels = {BvhChannel::Zrotation, BvhChannel::Yposition};
  const double values[] = {45, 7};
  EXPECT_EQ(bvh_local_translation(j, values), Vec3(1, 7, 100));
  j.channels = {BvhChannel::Xposition, BvhChannel::Yposition, BvhChannel::Zposition};
  const double xyz[] = {3, 4, 5};
  EXPECT_EQ(bvh_local_translation(j, xyz), Vec3(3, 4, 5));
}

TEST(BvhKinematics, MaskComputesOnlyTheAncestorClosure) {
  const BvhFile f = parse_bvh(kTwoJoints, "two.bvh");
  const std::vector<char> mask = bvh_ancestor_closure(f, {1, 99, -1});
  EXPECT_EQ(mask, (std::vector<char>{1, 1}));
  EXPECT_EQ(bvh_ancestor_closure(f, {0}), (std::vector<char>{1, 0}));
  BvhPose full, masked;
  bvh_forward_kinematics(f, 0, full);
  bvh_forward_kinematics(f, 0, masked, &mask);
  EXPECT_EQ(full.p_F_joint, masked.p_F_joint);
  EXPECT_EQ(full.p_F_end_site, masked.p_F_end_site);
}

std::vector<std::string> shared_bvh_clips() {
  std::vector<std::string> out;
  const std::string dir = test::shared_data("bvh");
  if (dir.empty()) return out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".bvh") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Global joint and End Site positions from our reader + FK agree with assimp's node animation on
// every real clip (every frame for short clips, 200 spread frames for long ones). assimp works in
// single precision, hence the relative tolerance.
TEST(BvhKinematics, AgreesWithAssimpOnEveryRealClip) {
  const auto clips = shared_bvh_clips();
  if (clips.empty()) GTEST_SKIP() << "shared BVH data not found under " << test::shared_data_dir();
  for (const std::string& path : clips) {
    SCOPED_TRACE(path);
    const BvhFile f = read_bvh(path);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    ASSERT_GE(scene->mNumAnimations, 1u);
    const aiAnimation* anim = scene->mAnimations[0];
    std::map<std::string, const aiNodeAnim*> channels;
    for (unsigned i = 0; i < anim->mNumChannels; ++i) channels[anim->mChannels[i]->mNodeName.C_Str()] = anim->mChannels[i];
    ASSERT_EQ(channels.size(), f.joints.size());
    ASSERT_EQ(static_cast<int>(anim->mChannels[0]->mNumRotationKeys), f.num_frames);

    std::vector<int> frames;
    const int step = std::max(1, f.num_frames / 200);
    for (int k = 0; k < f.num_frames; k += step) frames.push_back(k);
    frames.push_back(f.num_frames - 1);

    BvhPose pose;
    double max_error = 0, scale = 1;
    int compared = 0;
    for (int frame : frames) {
      bvh_forward_kinematics(f, frame, pose);
      scale = std::max(scale, pose.p_F_joint.cwiseAbs().maxCoeff());
      std::map<std::string, Vec3> p_assimp;
      std::function<void(const aiNode*, const Mat3&, const Vec3&)> walk = [&](const aiNode* node, const Mat3& R_parent,
                                                                               const Vec3& p_parent) {
        Mat3 R_local = Mat3::Identity();
        Vec3 t;
        const auto it = channels.find(node->mName.C_Str());
        if (it != channels.end()) {
          const aiNodeAnim* ch = it->second;
          const unsigned pk = std::min<unsigned>(static_cast<unsigned>(frame), ch->mNumPositionKeys - 1);
          const unsigned rk = std::min<unsigned>(static_cast<unsigned>(frame), ch->mNumRotationKeys - 1);
          const aiVector3D& v = ch->mPositionKeys[pk].mValue;
          const aiQuaternion& q = ch->mRotationKeys[rk].mValue;
          t = Vec3(v.x, v.y, v.z);
          R_local = Quat(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
        } else {
          const aiMatrix4x4& m = node->mTransformation;
          t = Vec3(m.a4, m.b4, m.c4);
        }
        const Mat3 R = R_parent * R_local;
        const Vec3 p = p_parent + R_parent * t;
        p_assimp[node->mName.C_Str()] = p;
        for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], R, p);
      };
      walk(scene->mRootNode, Mat3::Identity(), Vec3::Zero());
      for (std::size_t j = 0; j < f.joints.size(); ++j) {
        const auto it = p_assimp.find(f.joints[j].name);
        ASSERT_NE(it, p_assimp.end()) << f.joints[j].name;
        max_error = std::max(max_error, (it->second - pose.p_F_joint.col(static_cast<Eigen::Index>(j))).norm());
        ++compared;
      }
      for (std::size_t e = 0; e < f.end_sites.size(); ++e) {
        const auto it = p_assimp.find("EndSite_" + f.joints[static_cast<std::size_t>(f.end_sites[e].parent)].name);
        if (it == p_assimp.end()) continue;
        // A joint with several End Sites has one assimp node per End Site under the same name;
        // compare only joints with a single End Site.
        int siblings = 0;
        for (const BvhEndSite& s : f.end_sites) siblings += s.parent == f.end_sites[e].parent;
        if (siblings != 1) continue;
        max_error = std::max(max_error, (it->second - pose.p_F_end_site.col(static_cast<Eigen::Index>(e))).norm());
        ++compared;
      }
    }
    EXPECT_GT(compared, 0);
    std::printf("[ assimp ] %-44s %6d points, max |diff| %.2e (scale %.3g)\n",
                std::filesystem::path(path).filename().c_str(), compared, max_error, scale);
    EXPECT_LT(max_error, 2e-5 * scale) << "max |p_ours - p_assimp| = " << max_error << " (scale " << scale << ")";
  }
}

}  // namespace
}  // namespace rt
