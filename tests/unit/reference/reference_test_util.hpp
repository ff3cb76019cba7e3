#pragma once
/// Shared helpers of the reference reader/writer tests: a synthetic reference, the G1 joint order,
/// an InputError checker, and a runner for Debian's python3 + numpy.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/reference/reference.hpp"

namespace rt::test {

/// G1 29-DoF export order (URDF order = LAFAN1-retarget CSV order, shared/data/README.md §3.1).
inline std::vector<std::string> g1_joint_names() {
  return {"left_hip_pitch_joint",      "left_hip_roll_joint",      "left_hip_yaw_joint",
          "left_knee_joint",           "left_ankle_pitch_joint",   "left_ankle_roll_joint",
          "right_hip_pitch_joint",     "right_hip_roll_joint",     "right_hip_yaw_joint",
          "right_knee_joint",          "right_ankle_pitch_joint",  "right_ankle_roll_joint",
          "waist_yaw_joint",           "waist_roll_joint",         "waist_pitch_joint",
          "left_shoulder_pitch_joint", "left_shoulder_roll_joint", "left_shoulder_yaw_joint",
          "left_elbow_joint",          "left_wrist_roll_joint",    "left_wrist_pitch_joint",
          "left_wrist_yaw_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
          "right_shoulder_yaw_joint",  "right_elbow_joint",        "right_wrist_roll_joint",
          "right_wrist_pitch_joint",   "right_wrist_yaw_joint"};
}

/// A reference with T frames of random but plausible values (full double precision), random
/// unit root quaternions, a stepping contact pattern, COM and COP. Deterministic in `seed`.
inline Reference make_reference(int T, const std::vector<std::string>& joints, unsigned seed,
                                bool with_extras = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Reference r;
  r.robot_name = "g1";
  r.fps = 30;
  r.joint_names = joints;
  r.root_pos_W.resize(3, T);
  r.joint_pos.resize(static_cast<Eigen::Index>(joints.size()), T);
  for (int t = 0; t < T; ++t) {
    r.root_pos_W.col(t) << 0.01 * t + 1e-3 * u(rng), 0.2 * u(rng), 0.79 + 0.01 * u(rng);
    Quat q(u(rng), u(rng), u(rng), u(rng));
    q.normalize();
    r.root_quat_W.push_back(q);
    for (Eigen::Index j = 0; j < r.joint_pos.rows(); ++j) r.joint_pos(j, t) = 2.0 * u(rng);
  }
  // A value below 1e-4 and a negative zero exercise %g's exponent notation and the sign.
  if (T > 1 && r.joint_pos.rows() > 1) {
    r.joint_pos(0, 1) = -3.0517578125e-07;
    r.joint_pos(1, 1) = -0.0;
  }
  if (with_extras) {
    for (int t = 0; t < T; ++t) {
      r.contact[0].push_back(static_cast<std::uint8_t>((t / 7) % 2 == 0));
      r.contact[1].push_back(static_cast<std::uint8_t>((t / 5) % 3 != 1));
    }
    r.com_W.resize(3, T);
    r.cop_W.resize(2, T);
    for (int t = 0; t < T; ++t) {
      r.com_W.col(t) << u(rng) * 0.1, u(rng) * 0.1, 0.68 + 0.01 * u(rng);
      r.cop_W.col(t) << u(rng) * 0.1, u(rng) * 0.1;
    }
    r.extra_meta_json =
        R"({"urdf_sha256":"0123abcd","provenance":{"tool":"retarget 0.1.0","source":"walk.bvh","passes":)"
        R"([{"name":"ik","options":{"damping":0.001}}]},"metrics":{"landmark_error_median_m":0.0123456789012345}})";
  }
  return r;
}

/// Runs `fn`, expects an InputError whose one-line message contains every piece of `needles`,
/// and returns the message.
inline std::string expect_input_error(const std::function<void()>& fn, const std::vector<std::string>& needles) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    EXPECT_FALSE(e.location().empty()) << "no location: " << what;
    for (const std::string& n : needles) EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    return what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected an InputError, nothing was thrown";
  return {};
}

/// Whether Debian's /usr/bin/python3 with numpy is available (the numpy tests skip otherwise).
inline bool have_numpy() {
  return std::system("/usr/bin/python3 -c 'import numpy' > /dev/null 2>&1") == 0;
}

/// Runs `script` with /usr/bin/python3 (arguments appended), returns exit status and output.
inline int run_python(const std::string& dir, const std::string& script, const std::string& args, std::string& output) {
  const std::string script_path = dir + "/check.py";
  const std::string out_path = dir + "/python.out";
  std::ofstream(script_path) << script;
  const int rc = std::system(("/usr/bin/python3 " + script_path + " " + args + " > " + out_path + " 2>&1").c_str());
  std::ifstream in(out_path);
  std::stringstream ss;
  ss << in.rdbuf();
  output = ss.str();
  return rc;
}

}  // namespace rt::test
