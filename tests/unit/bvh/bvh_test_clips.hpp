#pragma once
/// Small BVH texts written for the tests, and a generator of synthetic humanoid clips.

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace rt::test {

/// The valid clip the bad-input corpus (tests/data/bvh/make_bad_corpus.py) is derived from.
inline const char* kTinyBvh = R"(HIERARCHY
ROOT Hips
{
	OFFSET 0.0 0.0 0.0
	CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
	JOINT Chest
	{
		OFFSET 0.0 10.0 0.0
		CHANNELS 3 Zrotation Xrotation Yrotation
		End Site
		{
			OFFSET 0.0 5.0 0.0
		}
	}
}
MOTION
Frames: 3
Frame Time: 0.033333
0 90 0 0 0 0 0 0 0
1 90 0 10 0 0 5 0 0
2 90 0 20 0 0 10 0 0
)";

/// Options of make_humanoid_bvh.
struct HumanoidClip {
  double metres_per_unit = 0.01;  ///< the clip is written in these units (cm by default)
  char up = 'y';                  ///< 'y': Y-up skeleton; 'z': the root carries +90 deg X (iClone-like)
  int tpose_frames = 0;           ///< leading frames in the rest T-pose before the motion
  int frames = 60;                ///< motion frames after the T-pose
  double frame_time_s = 1.0 / 30;
  std::string prefix;             ///< joint name prefix, e.g. "mixamorig:"
};

/// A Mixamo-named humanoid, 1.76 m tall (head joint 1.53 m above the floor, toe joints on it),
/// facing +Z in its Y-up frame, with a T-pose rest pose. Motion frames have the arms lowered by
/// 80 deg, the forearms swinging +-30 deg with a 30-frame period (straight at frames 0, 30, ...)
/// and the root moving forward 1 cm per frame; the legs stay straight.
inline std::string make_humanoid_bvh(const HumanoidClip& c) {
  const double s = 0.01 / c.metres_per_unit;  // cm -> file units
  std::ostringstream o;
  o.precision(10);
  int depth = 0;
  auto line = [&](const std::string& text) { o << std::string(static_cast<std::size_t>(depth), '\t') << text << "\n"; };
  auto offset = [&](double x, double y, double z) {
    std::ostringstream t;
    t.precision(10);
    t << "OFFSET " << x * s << " " << y * s << " " << z * s;
    line(t.str());
  };
  auto open = [&](const char* kind, const std::string& name, double x, double y, double z, bool root = false) {
    line(std::string(kind) + " " + c.prefix + name);
    line("{");
    ++depth;
    offset(x, y, z);
    line(root ? "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
              : "CHANNELS 3 Zrotation Xrotation Yrotation");
  };
  auto close = [&] {
    --depth;
    line("}");
  };
  auto end_site = [&](double x, double y, double z) {
    line("End Site");
    line("{");
    ++depth;
    offset(x, y, z);
    close();
  };
  // Joint order (= channel order): Hips, Spine, Spine1, Spine2, Neck, Head, LeftShoulder, LeftArm,
  // LeftForeArm, LeftHand, LeftHandMiddle1, Right..., LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase,
  // Right...
  o << "HIERARCHY\n";
  open("ROOT", "Hips", 0, 0, 0, true);
  open("JOINT", "Spine", 0, 10, 0);
  open("JOINT", "Spine1", 0, 12, 0);
  open("JOINT", "Spine2", 0, 12, 0);
  open("JOINT", "Neck", 0, 14, 0);
  open("JOINT", "Head", 0, 8, 0);
  end_site(0, 18, 0);
  close();
  close();
  for (int side : {1, -1}) {
    const std::string n = side > 0 ? "Left" : "Right";
    open("JOINT", n + "Shoulder", side * 3, 10, 0);
    open("JOINT", n + "Arm", side * 14, 0, 0);
    open("JOINT", n + "ForeArm", side * 28, 0, 0);
    open("JOINT", n + "Hand", side * 25, 0, 0);
    open("JOINT", n + "HandMiddle1", side * 10, 0, 0);
    end_site(side * 8, 0, 0);
    for (int k = 0; k < 5; ++k) close();
  }
  close();  // Spine2
  close();  // Spine1
  close();  // Spine
  for (int side : {1, -1}) {
    const std::string n = side > 0 ? "Left" : "Right";
    open("JOINT", n + "UpLeg", side * 9, -6, 0);
    open("JOINT", n + "Leg", 0, -42, 0);
    open("JOINT", n + "Foot", 0, -42, 0);
    open("JOINT", n + "ToeBase", 0, -7, 13);
    end_site(0, 0, 6);
    for (int k = 0; k < 4; ++k) close();
  }
  close();  // Hips
  const int total = c.tpose_frames + c.frames;
  o << "MOTION\nFrames: " << total << "\nFrame Time: " << c.frame_time_s << "\n";
  const int channels = 6 + 3 * (5 + 10 + 8);
  for (int f = 0; f < total; ++f) {
    std::vector<double> v(static_cast<std::size_t>(channels), 0.0);
    const bool tpose = f < c.tpose_frames;
    const double forward_cm = 1.0 * f;
    // Root position (cm, Y-up frame), then mapped by the root's base rotation.
    double px = 0, py = 97, pz = forward_cm;
    if (c.up == 'z') {
      const double y = py, z = pz;
      py = -z;  // Rx(+90): (x, y, z) -> (x, -z, y)
      pz = y;
      v[4] = 90;  // Xrotation of the root
    }
    v[0] = px * s;
    v[1] = py * s;
    v[2] = pz * s;
    if (!tpose) {
      const double phase = 2 * M_PI * f / 30.0;
      const int left_arm = 6 + 3 * (5 + 1), right_arm = 6 + 3 * (5 + 5 + 1);
      v[static_cast<std::size_t>(left_arm)] = -80;   // Zrotation: left arm (+X) down
      v[static_cast<std::size_t>(right_arm)] = 80;   // right arm (-X) down
      const int left_fore_arm = left_arm + 3, right_fore_arm = right_arm + 3;
      v[static_cast<std::size_t>(left_fore_arm + 2)] = 30 * std::sin(phase);  // Yrotation: swing
      v[static_cast<std::size_t>(right_fore_arm + 2)] = -30 * std::sin(phase);
    }
    for (int k = 0; k < channels; ++k) o << (k ? " " : "") << v[static_cast<std::size_t>(k)];
    o << "\n";
  }
  return o.str();
}

}  // namespace rt::test
