#include "retarget/motion/bvh/skeleton_profile.hpp"

#include <algorithm>
#include <unordered_map>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

constexpr char kBuiltIn[] = "built-in";

// Joint-name key used for matching: lower case, without a namespace prefix ("mixamorig:Hips" ->
// "hips").
std::string name_key(std::string_view name) {
  const auto colon = name.find_last_of(':');
  if (colon != std::string_view::npos) name = name.substr(colon + 1);
  return to_lower(trim(name));
}

JointRef joint(std::string name) { return {std::move(name), JointPoint::Joint}; }
JointRef end_site(std::string name) { return {std::move(name), JointPoint::EndSite}; }
JointRef midpoint(std::string name) { return {std::move(name), JointPoint::Midpoint}; }

// Expands the side placeholders of a name pattern: {Side} -> Left/Right, {S} -> L/R, {s} -> l/r.
std::string side_name(std::string pattern, bool left) {
  const std::pair<const char*, const char*> subs[] = {
      {"{Side}", left ? "Left" : "Right"}, {"{S}", left ? "L" : "R"}, {"{s}", left ? "l" : "r"}};
  for (const auto& [from, to] : subs) {
    for (auto pos = pattern.find(from); pos != std::string::npos; pos = pattern.find(from))
      pattern.replace(pos, std::char_traits<char>::length(from), to);
  }
  return pattern;
}

struct SideSpec {
  Landmark left;
  std::vector<JointRef> patterns;
};

// Builds a profile from central landmarks, side patterns (expanded for both sides) and a
// signature whose patterns are expanded for both sides too.
SkeletonProfile make_profile(std::string name, std::vector<std::pair<Landmark, std::vector<JointRef>>> central,
                             std::vector<SideSpec> sides, const std::vector<std::string>& signature) {
  SkeletonProfile p;
  p.name = std::move(name);
  for (auto& [l, refs] : central) p.landmarks[static_cast<std::size_t>(index(l))] = std::move(refs);
  for (const SideSpec& s : sides) {
    for (bool left : {true, false}) {
      std::vector<JointRef> refs;
      for (const JointRef& r : s.patterns) refs.push_back({side_name(r.joint, left), r.point});
      const Landmark l = left ? s.left : mirror(s.left);
      p.landmarks[static_cast<std::size_t>(index(l))] = std::move(refs);
    }
  }
  for (const std::string& sig : signature) {
    const std::string a = side_name(sig, true), b = side_name(sig, false);
    p.signature.push_back(a);
    if (b != a) p.signature.push_back(b);
  }
  return p;
}

std::vector<SkeletonProfile> make_builtin_profiles() {
  using L = Landmark;
  std::vector<SkeletonProfile> out;

  // CMU, cgspeed MotionBuilder-friendly release (B. Hahne). LowerBack, Neck and the *HipJoint /
  // *Shoulder joints have zero OFFSET; Neck1 (upper neck) is the neck base in height, Head the
  // skull base with the skull top as End Site.
  const std::vector<std::pair<L, std::vector<JointRef>>> cmu_mb_central = {
      {L::Spine, {joint("Spine")}},
      {L::Chest, {joint("Spine1")}},
      {L::Neck, {joint("Neck1"), joint("Neck")}},
      {L::Head, {midpoint("Head")}}};
  const std::vector<SideSpec> cmu_mb_legs_arms = {
      {L::LeftHip, {joint("{Side}UpLeg")}},      {L::LeftKnee, {joint("{Side}Leg")}},
      {L::LeftAnkle, {joint("{Side}Foot")}},     {L::LeftToe, {joint("{Side}ToeBase")}},
      {L::LeftShoulder, {joint("{Side}Arm")}},   {L::LeftElbow, {joint("{Side}ForeArm")}},
      {L::LeftWrist, {joint("{Side}Hand")}}};
  {
    auto sides = cmu_mb_legs_arms;
    sides.push_back({L::LeftHand, {joint("{S}Fingers"), joint("{Side}FingerBase")}});
    out.push_back(make_profile("cmu_motionbuilder_2008", cmu_mb_central, sides,
                               {"{S}HipJoint", "LowerBack", "Neck1", "{Side}FingerBase", "{S}Fingers", "{S}Thumb"}));
  }
  {
    auto sides = cmu_mb_legs_arms;
    sides.push_back({L::LeftHand, {joint("{Side}HandIndex1"), joint("{Side}FingerBase")}});
    out.push_back(make_profile("cmu_motionbuilder_2010", cmu_mb_central, sides,
                               {"{S}HipJoint", "LowerBack", "Neck1", "{Side}FingerBase", "{Side}HandIndex1", "{S}Thumb"}));
  }

  // CMU, cgspeed 3dsMax-friendly release: the same skeleton, other names (lowerneck has zero
  // OFFSET, Neck is the upper neck).
  out.push_back(make_profile(
      "cmu_3dsmax",
      {{L::Spine, {joint("Chest")}},
       {L::Chest, {joint("Chest2")}},
       {L::Neck, {joint("Neck"), joint("lowerneck")}},
       {L::Head, {midpoint("Head")}}},
      {{L::LeftHip, {joint("{Side}Hip")}},
       {L::LeftKnee, {joint("{Side}Knee")}},
       {L::LeftAnkle, {joint("{Side}Ankle")}},
       {L::LeftToe, {joint("{Side}Toe")}},
       {L::LeftShoulder, {joint("{Side}Shoulder")}},
       {L::LeftElbow, {joint("{Side}Elbow")}},
       {L::LeftWrist, {joint("{Side}Wrist")}},
       {L::LeftHand, {joint("{S}Fingers"), joint("{s}hand")}}},
      {"{S}HipJoint", "lowerback", "Chest2", "lowerneck", "{Side}Collar", "{s}hand", "{S}Fingers", "{S}Thumb"}));

  // CMU, cgspeed Daz/Poser-friendly release (also Poser / early Genesis names): no toe joint, the
  // foot ends in an End Site at the toes; lButtock sits above the hip joint (lThigh).
  out.push_back(make_profile(
      "cmu_daz",
      {{L::Spine, {joint("abdomen"), joint("abdomenLower")}},
       {L::Chest, {joint("chest"), joint("chestUpper")}},
       {L::Neck, {joint("neck"), joint("neckLower")}},
       {L::Head, {midpoint("head")}}},
      {{L::LeftHip, {joint("{s}Thigh"), joint("{s}ThighBend")}},
       {L::LeftKnee, {joint("{s}Shin")}},
       {L::LeftAnkle, {joint("{s}Foot")}},
       {L::LeftToe, {joint("{s}Toe"), end_site("{s}Foot")}},
       {L::LeftShoulder, {joint("{s}Shldr"), joint("{s}ShldrBend")}},
       {L::LeftElbow, {joint("{s}ForeArm"), joint("{s}ForearmBend")}},
       {L::LeftWrist, {joint("{s}Hand")}},
       {L::LeftHand, {joint("{s}Mid1"), end_site("{s}Hand")}}},
      {"abdomen", "{s}Collar", "{s}Shldr", "{s}Buttock", "{s}Thigh", "{s}Shin"}));

  // iClone / Character Creator (CC3) export: CC_Base_* names, root RL_BoneRoot (constant -90 deg X
  // rotation, the skeleton is authored Z-up) or CC_Base_Hip.
  out.push_back(make_profile(
      "iclone_cc_base",
      {{L::Spine, {joint("CC_Base_Spine01"), joint("CC_Base_Waist")}},
       {L::Chest, {joint("CC_Base_Spine02")}},
       {L::Neck, {joint("CC_Base_NeckTwist01")}},
       {L::Head, {midpoint("CC_Base_Head")}}},
      {{L::LeftHip, {joint("CC_Base_{S}_Thigh")}},
       {L::LeftKnee, {joint("CC_Base_{S}_Calf")}},
       {L::LeftAnkle, {joint("CC_Base_{S}_Foot")}},
       {L::LeftToe, {joint("CC_Base_{S}_ToeBase")}},
       {L::LeftShoulder, {joint("CC_Base_{S}_Upperarm")}},
       {L::LeftElbow, {joint("CC_Base_{S}_Forearm")}},
       {L::LeftWrist, {joint("CC_Base_{S}_Hand")}},
       {L::LeftHand, {joint("CC_Base_{S}_Mid1")}}},
      {"RL_BoneRoot", "CC_Base_Hip", "CC_Base_Pelvis", "CC_Base_Waist", "CC_Base_Spine01", "CC_Base_Spine02",
       "CC_Base_NeckTwist01", "CC_Base_{S}_Clavicle"}));

  // Bandai Namco Research Motion Dataset: every joint has 6 channels, rest offsets along local X.
  // The End Sites have zero OFFSET, so the hand landmark is not available from Hand_L's End Site.
  out.push_back(make_profile(
      "bandai_namco",
      {{L::Spine, {joint("Spine")}},
       {L::Chest, {joint("Chest")}},
       {L::Neck, {joint("Neck")}},
       {L::Head, {midpoint("Head")}}},
      {{L::LeftHip, {joint("UpperLeg_{S}")}},
       {L::LeftKnee, {joint("LowerLeg_{S}")}},
       {L::LeftAnkle, {joint("Foot_{S}")}},
       {L::LeftToe, {joint("Toes_{S}")}},
       {L::LeftShoulder, {joint("UpperArm_{S}")}},
       {L::LeftElbow, {joint("LowerArm_{S}")}},
       {L::LeftWrist, {joint("Hand_{S}")}},
       {L::LeftHand, {end_site("Hand_{S}")}}},
      {"joint_Root", "UpperLeg_{S}", "LowerLeg_{S}", "Toes_{S}", "Shoulder_{S}", "UpperArm_{S}", "LowerArm_{S}"}));

  // GAMES-105 course skeleton (RootJoint, lHip, ...): torso_head is the neck top, its End Site the
  // top of the head.
  out.push_back(make_profile(
      "games105",
      {{L::Spine, {joint("pelvis_lowerback")}},
       {L::Chest, {joint("lowerback_torso")}},
       {L::Neck, {joint("torso_head")}},
       {L::Head, {midpoint("torso_head")}}},
      {{L::LeftHip, {joint("{s}Hip")}},
       {L::LeftKnee, {joint("{s}Knee")}},
       {L::LeftAnkle, {joint("{s}Ankle")}},
       {L::LeftToe, {joint("{s}ToeJoint")}},
       {L::LeftShoulder, {joint("{s}Shoulder")}},
       {L::LeftElbow, {joint("{s}Elbow")}},
       {L::LeftWrist, {joint("{s}Wrist")}},
       {L::LeftHand, {end_site("{s}Wrist")}}},
      {"RootJoint", "{s}ToeJoint", "pelvis_lowerback", "lowerback_torso", "torso_head", "{s}Torso_Clavicle"}));

  // CMU ASF/AMC (the library's original skeleton, read through the equivalent BVH of
  // asf_motion.hpp: a joint at every bone's start). lhipjoint runs from the root to the hip, so the
  // femur starts at the hip centre; the head joint is the skull base, its End Site the top.
  out.push_back(make_profile(
      "cmu_asf",
      {{L::Spine, {joint("upperback")}},
       {L::Chest, {joint("thorax")}},
       {L::Neck, {joint("upperneck"), joint("lowerneck")}},
       {L::Head, {midpoint("head")}}},
      {{L::LeftHip, {joint("{s}femur")}},
       {L::LeftKnee, {joint("{s}tibia")}},
       {L::LeftAnkle, {joint("{s}foot")}},
       {L::LeftToe, {joint("{s}toes"), end_site("{s}foot")}},
       {L::LeftShoulder, {joint("{s}humerus")}},
       {L::LeftElbow, {joint("{s}radius")}},
       {L::LeftWrist, {joint("{s}wrist")}},
       {L::LeftHand, {joint("{s}fingers"), joint("{s}hand")}}},
      {"{s}femur", "{s}tibia", "{s}humerus", "{s}radius", "thorax"}));

  // Ubisoft La Forge Animation Dataset (LAFAN1): Mixamo-like names without the ToeBase/Hand_End
  // joints; every End Site has a zero OFFSET, so the head landmark falls back to the Head joint and
  // the hand landmark is not available (as for Bandai Namco).
  out.push_back(make_profile(
      "lafan1",
      {{L::Spine, {joint("Spine")}},
       {L::Chest, {joint("Spine2"), joint("Spine1")}},
       {L::Neck, {joint("Neck")}},
       {L::Head, {midpoint("Head")}}},
      {{L::LeftHip, {joint("{Side}UpLeg")}},
       {L::LeftKnee, {joint("{Side}Leg")}},
       {L::LeftAnkle, {joint("{Side}Foot")}},
       {L::LeftToe, {joint("{Side}Toe")}},
       {L::LeftShoulder, {joint("{Side}Arm")}},
       {L::LeftElbow, {joint("{Side}ForeArm")}},
       {L::LeftWrist, {joint("{Side}Hand")}},
       {L::LeftHand, {end_site("{Side}Hand")}}},
      {"{Side}Toe", "Spine2"}));

  // Mixamo naming (optionally `mixamorig:`-prefixed), also used by the PyMO demo clips, whose
  // minimal skeleton has a single Spine joint (it then serves as spine and chest) and no neck.
  out.push_back(make_profile(
      "mixamo",
      {{L::Spine, {joint("Spine")}},
       {L::Chest, {joint("Spine2"), joint("Spine1"), joint("Spine")}},
       {L::Neck, {joint("Neck")}},
       {L::Head, {midpoint("Head")}}},
      {{L::LeftHip, {joint("{Side}UpLeg")}},
       {L::LeftKnee, {joint("{Side}Leg")}},
       {L::LeftAnkle, {joint("{Side}Foot")}},
       {L::LeftToe, {joint("{Side}ToeBase")}},
       {L::LeftShoulder, {joint("{Side}Arm")}},
       {L::LeftElbow, {joint("{Side}ForeArm")}},
       {L::LeftWrist, {joint("{Side}Hand")}},
       {L::LeftHand,
        {joint("{Side}HandMiddle1"), joint("{Side}HandIndex1"), joint("{Side}Hand_End"), end_site("{Side}Hand")}}},
      {"Spine2", "HeadTop_End", "{Side}HandThumb1", "{Side}HandMiddle1", "{Side}Hand_End", "{Side}Toe_End"}));
  return out;
}

JointPoint parse_point(const YamlView& v) {
  const std::string s = v.as_string();
  if (s == "joint") return JointPoint::Joint;
  if (s == "end_site") return JointPoint::EndSite;
  if (s == "midpoint") return JointPoint::Midpoint;
  v.fail("unknown point '" + s + "' (expected joint, end_site or midpoint)");
}

JointRef parse_joint_ref(const YamlView& v) {
  if (v.is_scalar()) {
    const std::string name = v.as_string();
    if (trim(name).empty()) v.fail("empty joint name");
    return joint(name);
  }
  if (!v.is_map()) v.fail("expected a joint name, {joint: NAME, point: joint|end_site|midpoint} or a list of these");
  v.check_keys({"joint", "point"});
  JointRef r;
  r.joint = v.at("joint").as_string();
  if (trim(r.joint).empty()) v.at("joint").fail("empty joint name");
  if (auto p = v.find("point")) r.point = parse_point(*p);
  return r;
}

}  // namespace

std::string_view joint_point_name(JointPoint point) {
  switch (point) {
    case JointPoint::Joint: return "joint";
    case JointPoint::EndSite: return "end_site";
    case JointPoint::Midpoint: return "midpoint";
  }
  return "invalid";
}

const std::vector<Landmark>& required_skeleton_landmarks() {
  static const std::vector<Landmark> required = {
      Landmark::Head,          Landmark::LeftHip,       Landmark::RightHip,   Landmark::LeftKnee,
      Landmark::RightKnee,     Landmark::LeftAnkle,     Landmark::RightAnkle, Landmark::LeftToe,
      Landmark::RightToe,      Landmark::LeftShoulder,  Landmark::RightShoulder, Landmark::LeftElbow,
      Landmark::RightElbow,    Landmark::LeftWrist,     Landmark::RightWrist};
  return required;
}

const std::vector<SkeletonProfile>& builtin_skeleton_profiles() {
  static const std::vector<SkeletonProfile> profiles = make_builtin_profiles();
  return profiles;
}

SkeletonProfile parse_skeleton_profile(const YamlView& root) {
  root.expect_map();
  root.check_keys({"name", "base", "landmarks"});
  SkeletonProfile p;
  if (auto base = root.find("base")) {
    const std::string base_name = base->as_string();
    const auto& builtins = builtin_skeleton_profiles();
    const auto it = std::find_if(builtins.begin(), builtins.end(),
                                 [&](const SkeletonProfile& b) { return b.name == base_name; });
    if (it == builtins.end()) {
      std::vector<std::string> names;
      for (const auto& b : builtins) names.push_back(b.name);
      base->fail("unknown built-in profile '" + base_name + "' (built-in: " + join(names, ", ") + ")");
    }
    p = *it;
  }
  p.name = root.at("name").as_string();
  if (trim(p.name).empty()) root.at("name").fail("empty profile name");
  p.origin = root.file();
  p.signature.clear();  // a user profile is chosen explicitly, never ranked

  const YamlView landmarks = root.at("landmarks");
  landmarks.expect_map();
  for (const std::string& key : landmarks.keys()) {
    const auto l = landmark_from_name(key);
    const YamlView child(landmarks.node()[key], root.file(), "landmarks." + key);
    if (!l) {
      std::vector<std::string> names;
      for (Landmark k : all_landmarks()) names.emplace_back(landmark_name(k));
      child.fail("unknown landmark (known: " + join(names, ", ") + ")");
    }
    const auto i = static_cast<std::size_t>(index(*l));
    p.locations[i] = child.location();
    std::vector<JointRef>& refs = p.landmarks[i];
    refs.clear();
    if (child.node().IsNull()) continue;  // `left_hand: null` removes an inherited landmark
    if (child.is_sequence()) {
      if (child.size() == 0) child.fail("empty list of joints");
      for (std::size_t k = 0; k < child.size(); ++k) refs.push_back(parse_joint_ref(child.at(k)));
    } else {
      refs.push_back(parse_joint_ref(child));
    }
  }
  return p;
}

SkeletonProfile load_skeleton_profile(const std::string& path) {
  return parse_skeleton_profile(YamlView::load_file(path));
}

SkeletonBinding bind_skeleton_profile(const SkeletonProfile& profile, const BvhFile& file) {
  std::unordered_map<std::string, int> by_key;
  for (std::size_t j = 0; j < file.joints.size(); ++j) by_key.emplace(name_key(file.joints[j].name), static_cast<int>(j));
  // First End Site with a non-zero OFFSET under each joint (a zero one carries no information).
  std::vector<int> end_site_of(file.joints.size(), -1);
  for (std::size_t e = file.end_sites.size(); e-- > 0;) {
    const BvhEndSite& s = file.end_sites[e];
    if (s.parent >= 0 && s.parent < static_cast<int>(file.joints.size()) && s.offset.norm() > 0)
      end_site_of[static_cast<std::size_t>(s.parent)] = static_cast<int>(e);
  }
  const auto find = [&](const std::string& name) {
    const auto it = by_key.find(name_key(name));
    return it == by_key.end() ? -1 : it->second;
  };

  SkeletonBinding b;
  b.profile = profile.name;
  b.origin = profile.origin;
  const bool user = profile.origin != kBuiltIn;
  for (Landmark l : all_landmarks()) {
    const auto i = static_cast<std::size_t>(index(l));
    const std::vector<JointRef>& refs = profile.landmarks[i];
    LandmarkSource& src = b.sources[i];
    for (const JointRef& r : refs) {
      const int j = find(r.joint);
      if (j < 0) continue;
      const int e = end_site_of[static_cast<std::size_t>(j)];
      if (r.point == JointPoint::EndSite && e < 0) continue;
      src.joint = j;
      src.end_site = r.point == JointPoint::Joint ? -1 : e;
      src.point = r.point == JointPoint::Joint || e < 0 ? JointPoint::Joint : r.point;
      break;
    }
    if (!src.available() && user && !refs.empty()) {
      std::vector<std::string> tried;
      for (const JointRef& r : refs)
        tried.push_back(r.point == JointPoint::EndSite ? "End Site of " + r.joint : r.joint);
      const std::string location = profile.locations[i].empty() ? profile.origin : profile.locations[i];
      throw InputError(location, "landmarks." + std::string(landmark_name(l)) + ": not found in the skeleton of " +
                                     file.name + " (tried: " + join(tried, ", ") + ")");
    }
  }
  b.pelvis_from_hips = profile.landmarks[static_cast<std::size_t>(index(Landmark::Pelvis))].empty();
  for (const std::string& s : profile.signature) b.signature_hits += find(s) >= 0;
  for (Landmark l : required_skeleton_landmarks())
    if (!b.has(l)) b.missing_required.push_back(l);
  return b;
}

SkeletonBinding recognise_skeleton(const BvhFile& file) {
  const auto& profiles = builtin_skeleton_profiles();
  std::vector<SkeletonBinding> bindings;
  for (const SkeletonProfile& p : profiles) bindings.push_back(bind_skeleton_profile(p, file));
  const auto landmark_count = [](const SkeletonBinding& b) {
    int n = 0;
    for (Landmark l : all_landmarks()) n += b.has(l);
    return n;
  };
  int best = -1;
  for (std::size_t i = 0; i < bindings.size(); ++i) {
    const SkeletonBinding& b = bindings[i];
    if (!b.missing_required.empty()) continue;
    if (best < 0) {
      best = static_cast<int>(i);
      continue;
    }
    const SkeletonBinding& c = bindings[static_cast<std::size_t>(best)];
    if (b.signature_hits > c.signature_hits ||
        (b.signature_hits == c.signature_hits && landmark_count(b) > landmark_count(c)))
      best = static_cast<int>(i);
  }
  if (best >= 0) return bindings[static_cast<std::size_t>(best)];

  // Not recognised: report the closest profile (fewest missing required landmarks, then most
  // signature names) so that the user sees what is missing.
  std::size_t closest = 0;
  for (std::size_t i = 1; i < bindings.size(); ++i) {
    const auto& b = bindings[i];
    const auto& c = bindings[closest];
    if (b.missing_required.size() < c.missing_required.size() ||
        (b.missing_required.size() == c.missing_required.size() && b.signature_hits > c.signature_hits))
      closest = i;
  }
  const SkeletonBinding& c = bindings[closest];
  const SkeletonProfile& cp = profiles[closest];
  std::vector<std::string> missing;
  for (Landmark l : c.missing_required) {
    std::vector<std::string> tried;
    for (const JointRef& r : cp.landmarks[static_cast<std::size_t>(index(l))]) tried.push_back(r.joint);
    missing.push_back(std::string(landmark_name(l)) + " (no " + join(tried, " or ") + ")");
  }
  const std::string root = file.joints.empty() ? std::string("none") : file.joints.front().name;
  throw InputError(file.name, "skeleton not recognised (root joint '" + root + "', " +
                                  std::to_string(file.joints.size()) + " joints): the closest built-in profile '" +
                                  cp.name + "' is missing " + join(missing, ", ") +
                                  "; write a skeleton profile YAML mapping landmarks to joints (name: my_rig, "
                                  "landmarks: {left_knee: JointName, ...}) and pass it with --skeleton-profile FILE.yaml");
}

}  // namespace rt
