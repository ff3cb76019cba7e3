// Skeleton profiles: built-in recognition, name matching, user profile YAML and its errors,
// unrecognised skeletons.

#include <gtest/gtest.h>

#include <fstream>

#include "bvh_test_clips.hpp"
#include "formats/bvh/bvh_reader.hpp"
#include "retarget/core/error.hpp"
#include "retarget/motion/bvh/bvh_motion.hpp"
#include "retarget/motion/bvh/skeleton_profile.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using L = Landmark;

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = test::scratch_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

BvhFile humanoid(const std::string& prefix = "") {
  test::HumanoidClip c;
  c.frames = 5;
  c.prefix = prefix;
  return parse_bvh(test::make_humanoid_bvh(c), "humanoid.bvh");
}

// Renames joints of a BVH text (whole names only, in the hierarchy).
std::string rename(std::string text, const std::vector<std::pair<std::string, std::string>>& names) {
  for (const auto& [from, to] : names) {
    for (const char* kw : {"ROOT ", "JOINT "}) {
      const std::string a = kw + from + "\n", b = kw + to + "\n";
      for (auto p = text.find(a); p != std::string::npos; p = text.find(a, p + b.size())) text.replace(p, a.size(), b);
    }
  }
  return text;
}

TEST(SkeletonProfile, BuiltinsAreWellFormed) {
  const auto& profiles = builtin_skeleton_profiles();
  std::vector<std::string> names;
  for (const SkeletonProfile& p : profiles) {
    names.push_back(p.name);
    EXPECT_EQ(p.origin, "built-in");
    EXPECT_FALSE(p.signature.empty()) << p.name;
    for (Landmark l : required_skeleton_landmarks()) EXPECT_FALSE(p.landmarks[static_cast<std::size_t>(index(l))].empty()) << p.name << " " << landmark_name(l);
    EXPECT_TRUE(p.landmarks[static_cast<std::size_t>(index(L::Pelvis))].empty()) << p.name << ": pelvis comes from the hips";
    EXPECT_TRUE(p.landmarks[static_cast<std::size_t>(index(L::LeftHeel))].empty()) << p.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cmu_motionbuilder_2008", "cmu_motionbuilder_2010", "cmu_3dsmax", "cmu_daz",
                                             "iclone_cc_base", "bandai_namco", "games105", "cmu_asf", "lafan1", "mixamo"}));
}

TEST(SkeletonProfile, MixamoNamesMatchWithAndWithoutNamespaceAndAnyCase) {
  for (const std::string prefix : {"", "mixamorig:", "Char1:"}) {
    const SkeletonBinding b = recognise_skeleton(humanoid(prefix));
    EXPECT_EQ(b.profile, "mixamo") << prefix;
    EXPECT_TRUE(b.missing_required.empty());
    EXPECT_TRUE(b.pelvis_from_hips);
    for (Landmark l : all_landmarks()) EXPECT_EQ(b.has(l), l != L::LeftHeel && l != L::RightHeel) << landmark_name(l);
    EXPECT_EQ(b.sources[static_cast<std::size_t>(index(L::Head))].point, JointPoint::Midpoint);
  }
  test::HumanoidClip c;
  c.frames = 2;
  std::string upper = test::make_humanoid_bvh(c);
  upper = rename(upper, {{"LeftUpLeg", "LEFTUPLEG"}, {"Hips", "hips"}});
  EXPECT_EQ(recognise_skeleton(parse_bvh(upper, "upper.bvh")).profile, "mixamo");
}

TEST(SkeletonProfile, SignatureNamesSeparateConventionsSharingNames) {
  // The humanoid renamed to CMU MotionBuilder 2010 naming (LeftFingerBase, LeftHandIndex1, ...):
  // Mixamo's landmarks still resolve, but the signature picks the CMU profile.
  test::HumanoidClip c;
  c.frames = 2;
  const std::string text = rename(test::make_humanoid_bvh(c), {{"Spine1", "LowerBack"},
                                                              {"Spine2", "Spine1"},
                                                              {"LeftHandMiddle1", "LeftHandIndex1"},
                                                              {"RightHandMiddle1", "RightHandIndex1"},
                                                              {"LeftShoulder", "LeftFingerBase"},
                                                              {"RightShoulder", "RightFingerBase"},
                                                              {"Neck", "Neck1"}});
  const SkeletonBinding b = recognise_skeleton(parse_bvh(text, "mb2010.bvh"));
  EXPECT_EQ(b.profile, "cmu_motionbuilder_2010");
  EXPECT_GE(b.signature_hits, 4);
}

TEST(SkeletonProfile, UnrecognisedSkeletonNamesMissingLandmarksAndTheFlag) {
  test::HumanoidClip c;
  c.frames = 2;
  const std::string text = rename(test::make_humanoid_bvh(c), {{"LeftLeg", "Bone07"}, {"RightLeg", "Bone11"}, {"Head", "Bone05"}});
  const BvhFile f = parse_bvh(text, "odd.bvh");
  try {
    recognise_skeleton(f);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), "odd.bvh");
    const std::string m = e.message();
    EXPECT_NE(m.find("skeleton not recognised"), std::string::npos) << m;
    EXPECT_NE(m.find("'mixamo'"), std::string::npos) << m;
    EXPECT_NE(m.find("head (no Head)"), std::string::npos) << m;
    EXPECT_NE(m.find("left_knee (no LeftLeg)"), std::string::npos) << m;
    EXPECT_NE(m.find("right_knee (no RightLeg)"), std::string::npos) << m;
    EXPECT_NE(m.find("--skeleton-profile FILE.yaml"), std::string::npos) << m;
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  // load_bvh_motion reports the same error.
  EXPECT_THROW(bvh_to_human_motion(f), InputError);
}

TEST(SkeletonProfile, UserProfileMapsAnUnknownSkeleton) {
  test::HumanoidClip c;
  c.frames = 4;
  const std::string text = rename(test::make_humanoid_bvh(c), {{"LeftLeg", "Bone07"}, {"RightLeg", "Bone11"}, {"Head", "Bone05"}});
  const BvhFile f = parse_bvh(text, "odd.bvh");
  const std::string yaml = write_file("rig.yaml", R"(name: my_rig
base: mixamo
landmarks:
  left_knee: Bone07
  right_knee: [NoSuchJoint, {joint: Bone11, point: joint}]
  head: {joint: Bone05, point: midpoint}
  left_hand: null
  spine: Spine1
)");
  const SkeletonProfile p = load_skeleton_profile(yaml);
  EXPECT_EQ(p.name, "my_rig");
  EXPECT_EQ(p.origin, yaml);
  EXPECT_EQ(p.locations[static_cast<std::size_t>(index(L::LeftKnee))], yaml + ":4");

  MotionLoadOptions o;
  o.profile_path = yaml;
  const HumanMotion m = bvh_to_human_motion(f, o);
  EXPECT_EQ(m.source.profile, "my_rig");
  EXPECT_EQ(m.source.details.at("profile_origin"), yaml);
  EXPECT_FALSE(m.has(L::LeftHand));
  EXPECT_TRUE(m.has(L::RightHand));
  // Same landmarks as the built-in profile on the original names.
  const HumanMotion ref = bvh_to_human_motion(humanoid());
  for (Landmark l : {L::LeftKnee, L::RightKnee, L::Head, L::Pelvis})
    EXPECT_LT((m[l].p_W.leftCols(4) - ref[l].p_W.leftCols(4)).cwiseAbs().maxCoeff(), 1e-12) << landmark_name(l);
  // spine overridden: Spine1 instead of Spine, 12 cm higher.
  EXPECT_NEAR(m[L::Spine].p_W(2, 0) - ref[L::Spine].p_W(2, 0), 0.12, 1e-9);
}

TEST(SkeletonProfile, UserProfilePelvisAndEndSitePoints) {
  const std::string yaml = write_file("full.yaml", R"(name: explicit
landmarks:
  pelvis: Hips
  head: Head
  left_hip: LeftUpLeg
  right_hip: RightUpLeg
  left_knee: LeftLeg
  right_knee: RightLeg
  left_ankle: LeftFoot
  right_ankle: RightFoot
  left_toe: {joint: LeftToeBase, point: end_site}
  right_toe: {joint: RightToeBase, point: end_site}
  left_shoulder: LeftArm
  right_shoulder: RightArm
  left_elbow: LeftForeArm
  right_elbow: RightForeArm
  left_wrist: LeftHand
  right_wrist: RightHand
)");
  const BvhFile f = humanoid();
  const SkeletonBinding b = bind_skeleton_profile(load_skeleton_profile(yaml), f);
  EXPECT_TRUE(b.missing_required.empty());
  EXPECT_FALSE(b.pelvis_from_hips);
  const LandmarkSource& toe = b.sources[static_cast<std::size_t>(index(L::LeftToe))];
  EXPECT_EQ(toe.point, JointPoint::EndSite);
  EXPECT_GE(toe.end_site, 0);
  EXPECT_EQ(f.end_sites[static_cast<std::size_t>(toe.end_site)].parent, f.find_joint("LeftToeBase"));
  EXPECT_FALSE(b.has(L::Spine));

  MotionLoadOptions o;
  o.profile_path = yaml;
  const HumanMotion m = bvh_to_human_motion(f, o);
  // Pelvis = the Hips joint, 6 cm above the hip joint centres.
  EXPECT_NEAR(m[L::Pelvis].p_W(2, 0) - m[L::LeftHip].p_W(2, 0), 0.06, 1e-9);
  // Toe = End Site (toe tip, 6 cm ahead of the ToeBase joint at the same height): on the floor.
  EXPECT_NEAR(m[L::LeftToe].p_W(2, 0), 0.0, 1e-9);
}

void expect_profile_error(const std::string& yaml_text, const std::string& location_suffix, const std::string& message,
                          const BvhFile* clip = nullptr) {
  const std::string path = write_file("bad.yaml", yaml_text);
  try {
    if (clip) {
      MotionLoadOptions o;
      o.profile_path = path;
      bvh_to_human_motion(*clip, o);
    } else {
      load_skeleton_profile(path);
    }
    ADD_FAILURE() << "accepted:\n" << yaml_text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.location(), path + location_suffix) << e.what();
    EXPECT_NE(e.message().find(message), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(SkeletonProfile, UserProfileErrorsCarryFileLineAndKeyPath) {
  expect_profile_error("name: x\nlandmarks:\n  left_kne: LeftLeg\n", ":3", "landmarks.left_kne: unknown landmark");
  expect_profile_error("name: x\nlandmark:\n  left_knee: LeftLeg\n", ":2", "landmark: unknown key (allowed: name, base, landmarks)");
  expect_profile_error("name: x\nlandmarks:\n  head: {joint: Head, point: top}\n", ":3",
                       "landmarks.head.point: unknown point 'top' (expected joint, end_site or midpoint)");
  expect_profile_error("name: x\nlandmarks:\n  head: {jont: Head}\n", ":3", "landmarks.head.jont: unknown key");
  expect_profile_error("name: x\nbase: vicon\nlandmarks: {}\n", ":2", "base: unknown built-in profile 'vicon'");
  expect_profile_error("landmarks: {}\n", ":1", "missing required key 'name'");
  expect_profile_error("name: x\nlandmarks:\n  head: []\n", ":3", "landmarks.head: empty list of joints");
  expect_profile_error("name: [x\n", ":2", "YAML syntax error");

  const BvhFile f = humanoid();
  expect_profile_error("name: x\nbase: mixamo\nlandmarks:\n  left_knee: Knee_L\n", ":4",
                       "landmarks.left_knee: not found in the skeleton of humanoid.bvh (tried: Knee_L)", &f);
  expect_profile_error("name: x\nbase: mixamo\nlandmarks:\n  left_knee: [Knee_L, {joint: LeftLeg, point: end_site}]\n", ":4",
                       "(tried: Knee_L, End Site of LeftLeg)", &f);
  // End Site requested on a joint without one: not found either; on a joint with one: accepted.
  expect_profile_error("name: x\nbase: mixamo\nlandmarks:\n  left_knee: {joint: LeftLeg, point: end_site}\n", ":4",
                       "landmarks.left_knee: not found", &f);
  MotionLoadOptions o;
  o.profile_path = write_file("ok.yaml", "name: x\nbase: mixamo\nlandmarks:\n  head: {joint: Head, point: end_site}\n");
  EXPECT_EQ(bvh_to_human_motion(f, o).source.profile, "x");
  expect_profile_error("name: partial\nlandmarks:\n  head: Head\n", "",
                       "skeleton profile 'partial' does not give the required landmarks left_hip, right_hip", &f);
}

}  // namespace
}  // namespace rt
