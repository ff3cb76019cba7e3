#include "formats/reference/reference_npz.hpp"

#include <gtest/gtest.h>

#include "formats/reference/npz_file.hpp"
#include "formats/reference/reference_csv.hpp"
#include "reference_test_util.hpp"
#include "retarget/core/file_io.hpp"
#include "support/test_paths.hpp"

namespace rt {
namespace {

using npz::Array;
using npz::DType;
using npz::NamedArray;

// Two bodies with closed-form tracks; body 0 follows the reference root.
NpzBodyArrays make_bodies(const Reference& r) {
  const int T = r.num_frames();
  NpzBodyArrays b;
  b.body_names = {"pelvis", "left_ankle_roll_link"};
  b.p_W_body = {r.root_pos_W, Mat3X(3, T)};
  b.q_W_body = {r.root_quat_W, std::vector<Quat>()};
  b.v_W_body = {Mat3X(3, T), Mat3X(3, T)};
  b.w_W_body = {Mat3X(3, T), Mat3X(3, T)};
  for (int t = 0; t < T; ++t) {
    b.p_W_body[1].col(t) << 0.1 * t, 0.1, 0.05;
    b.q_W_body[1].push_back(Quat(AngleAxis(0.01 * t, Vec3::UnitZ())));
    for (int k = 0; k < 2; ++k) {
      b.v_W_body[static_cast<std::size_t>(k)].col(t) << t, k, -1;
      b.w_W_body[static_cast<std::size_t>(k)].col(t) << 0, 0.5 * k, t;
    }
  }
  return b;
}

void expect_equal_references(const Reference& a, const Reference& b) {
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.joint_names, b.joint_names);
  EXPECT_EQ(a.root_pos_W, b.root_pos_W);
  ASSERT_EQ(a.root_quat_W.size(), b.root_quat_W.size());
  for (std::size_t t = 0; t < a.root_quat_W.size(); ++t) EXPECT_EQ(a.root_quat_W[t].coeffs(), b.root_quat_W[t].coeffs());
  EXPECT_EQ(a.joint_pos, b.joint_pos);
  EXPECT_EQ(a.contact[0], b.contact[0]);
  EXPECT_EQ(a.contact[1], b.contact[1]);
  EXPECT_EQ(a.com_W, b.com_W);
  EXPECT_EQ(a.cop_W, b.cop_W);
}

TEST(ReferenceNpz, JointVelocitiesAreCentralDifferences) {
  MatX q(1, 4);
  q << 0, 1, 4, 9;
  const MatX v = joint_velocities(q, 10);
  EXPECT_DOUBLE_EQ(v(0, 0), 10);   // one-sided
  EXPECT_DOUBLE_EQ(v(0, 1), 20);   // (4 - 0) * 10 / 2
  EXPECT_DOUBLE_EQ(v(0, 2), 40);
  EXPECT_DOUBLE_EQ(v(0, 3), 50);
  EXPECT_EQ(joint_velocities(MatX::Ones(2, 1), 30), MatX::Zero(2, 1));
}

TEST(ReferenceNpz, RoundTripIsExactWithBodies) {
  const Reference r = test::make_reference(37, test::g1_joint_names(), 5);
  const NpzBodyArrays b = make_bodies(r);
  for (bool compress : {true, false}) {
    ReferenceNpzWriteOptions o;
    o.compress = compress;
    const std::string bytes = encode_reference_npz(r, &b, o);
    NpzBodyArrays back_b;
    const Reference back = decode_reference_npz(bytes, "r.npz", {}, &back_b);
    expect_equal_references(r, back);
    EXPECT_EQ(back.extra_meta_json, "{}");  // provenance lives in meta.json
    ASSERT_EQ(back_b.body_names, b.body_names);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(back_b.p_W_body[k], b.p_W_body[k]);
      EXPECT_EQ(back_b.v_W_body[k], b.v_W_body[k]);
      EXPECT_EQ(back_b.w_W_body[k], b.w_W_body[k]);
      for (int t = 0; t < 37; ++t)
        EXPECT_LT((back_b.q_W_body[k][static_cast<std::size_t>(t)].coeffs() - b.q_W_body[k][static_cast<std::size_t>(t)].coeffs()).norm(), 1e-15);
    }
  }
}

TEST(ReferenceNpz, Float32Option) {
  const Reference r = test::make_reference(10, {"a", "b"}, 9);
  ReferenceNpzWriteOptions o;
  o.float32 = true;
  const std::string bytes = encode_reference_npz(r, nullptr, o);
  const npz::NpzFile f = npz::decode_npz(bytes, "f.npz");
  EXPECT_EQ(f.find("joint_pos")->descr(), "<f4");
  EXPECT_EQ(f.find("fps")->descr(), "<f8");
  const Reference back = decode_reference_npz(bytes, "f.npz");
  EXPECT_LT((back.joint_pos - r.joint_pos).cwiseAbs().maxCoeff(), 1e-6);
  for (const Quat& q : back.root_quat_W) EXPECT_NEAR(q.norm(), 1.0, kQuatKeepNormTolerance);
}

TEST(ReferenceNpz, NumpyLoadsItWithBeyondMimicKeys) {
  if (!test::have_numpy()) GTEST_SKIP() << "/usr/bin/python3 with numpy not available";
  const std::string dir = test::scratch_dir();
  Reference r = test::make_reference(20, test::g1_joint_names(), 21);
  r.root_quat_W[3] = Quat(0.5, 0.5, -0.5, 0.5);  // w x y z = 0.5 0.5 -0.5 0.5
  const NpzBodyArrays b = make_bodies(r);
  write_reference_npz(dir + "/walk.npz", r, &b);
  // Expected values written by us for python to compare with, as plain text.
  std::string expect;
  char buf[64];
  for (int t = 0; t < 20; ++t)
    for (int j = 0; j < 29; ++j) {
      std::snprintf(buf, sizeof(buf), "%.17g\n", r.joint_pos(j, t));
      expect += buf;
    }
  write_file_atomic(dir + "/joint_pos.txt", expect);
  const std::string script = R"PY(
import sys, numpy as np
d = np.load(sys.argv[1])
T, J, B = 20, 29, 2
want = {"fps": ((1,), np.float64), "joint_names": ((J,), np.dtype("<U26")), "joint_pos": ((T, J), np.float64),
        "joint_vel": ((T, J), np.float64), "root_pos_w": ((T, 3), np.float64), "root_quat_w": ((T, 4), np.float64),
        "contacts": ((T, 2), np.bool_), "com_pos_w": ((T, 3), np.float64), "zmp_w": ((T, 2), np.float64),
        "cop_ref_w": ((T, 2), np.float64),
        "body_names": ((B,), np.dtype("<U20")), "body_pos_w": ((T, B, 3), np.float64),
        "body_quat_w": ((T, B, 4), np.float64), "body_lin_vel_w": ((T, B, 3), np.float64),
        "body_ang_vel_w": ((T, B, 3), np.float64)}
assert sorted(d.files) == sorted(want), d.files
for k, (shape, dtype) in want.items():
    assert d[k].shape == shape and d[k].dtype == dtype, (k, d[k].shape, d[k].dtype)
assert float(d["fps"][0]) == 30.0
assert np.array_equal(d["zmp_w"], d["cop_ref_w"])  # one plan, the issue's name and design.md's
assert d["joint_names"][0] == "left_hip_pitch_joint" and d["joint_names"][28] == "right_wrist_yaw_joint"
assert list(d["body_names"]) == ["pelvis", "left_ankle_roll_link"]
q = np.loadtxt(sys.argv[2]).reshape(T, J)
assert np.array_equal(d["joint_pos"], q)
v = np.gradient(q, 1.0 / 30.0, axis=0, edge_order=1)
assert np.allclose(d["joint_vel"], v, rtol=0, atol=1e-9), abs(d["joint_vel"] - v).max()
# w x y z: frame 3 was set to w=0.5 x=0.5 y=-0.5 z=0.5
assert np.array_equal(d["root_quat_w"][3], [0.5, 0.5, -0.5, 0.5]), d["root_quat_w"][3]
assert np.array_equal(d["body_quat_w"][3, 0], [0.5, 0.5, -0.5, 0.5])
ang = 0.01 * 7
assert np.allclose(d["body_quat_w"][7, 1], [np.cos(ang / 2), 0, 0, np.sin(ang / 2)], atol=1e-15)
assert np.allclose(np.linalg.norm(d["body_quat_w"], axis=2), 1.0)
assert np.array_equal(d["body_pos_w"][:, 0, :], d["root_pos_w"])
assert np.allclose(d["body_pos_w"][5, 1], [0.5, 0.1, 0.05])
assert np.array_equal(d["body_lin_vel_w"][4, 1], [4, 1, -1]) and np.array_equal(d["body_ang_vel_w"][4, 1], [0, 0.5, 4])
assert d["contacts"][:, 0].tolist() == [bool((t // 7) % 2 == 0) for t in range(T)]
print("ok")
)PY";
  std::string out;
  ASSERT_EQ(test::run_python(dir, script, dir + "/walk.npz " + dir + "/joint_pos.txt", out), 0) << out;
  EXPECT_EQ(out, "ok\n");
}

TEST(ReferenceNpz, ReadsBeyondMimicFileWithoutNamesOrRootKeys) {
  // The keys BeyondMimic's csv_to_npz writes: no joint_names, no root_* (body 0 is the root).
  const Reference r = test::make_reference(6, {"a", "b", "c"}, 4, false);
  const NpzBodyArrays b = make_bodies(r);
  const npz::NpzFile full = npz::decode_npz(encode_reference_npz(r, &b), "full.npz");
  std::vector<NamedArray> bm;
  for (const NamedArray& a : full.arrays)
    if (a.key != "joint_names" && a.key != "root_pos_w" && a.key != "root_quat_w" && a.key != "body_names") bm.push_back(a);
  bm.front().array = Array::from_ints({1}, {30}, DType::Int64);  // BeyondMimic stores fps=[int]
  const std::string bytes = npz::encode_npz(bm);

  ReferenceReadOptions o;
  test::expect_input_error([&] { decode_reference_npz(bytes, "bm.npz", o); }, {"bm.npz [joint_names.npy]", "--joint-order"});
  // The robot's own order is not a stated order: still refused.
  o.joint_names = {"a", "b", "c"};
  o.robot_name = "toy";
  test::expect_input_error([&] { decode_reference_npz(bytes, "bm.npz", o); }, {"bm.npz [joint_names.npy]", "--joint-order"});
  o.npz_joint_order = {"a", "b", "c", "d"};
  test::expect_input_error([&] { decode_reference_npz(bytes, "bm.npz", o); },
                           {"bm.npz@0x", "3 joint columns but the stated joint order has 4"});
  o.npz_joint_order = {"a", "b", "c"};
  NpzBodyArrays back_b;
  const Reference back = decode_reference_npz(bytes, "bm.npz", o, &back_b);
  expect_equal_references(r, back);
  EXPECT_EQ(back_b.body_names, (std::vector<std::string>{"body_0", "body_1"}));
}

TEST(ReferenceNpz, BadContentIsOneLineErrorWithLocation) {
  const Reference r = test::make_reference(8, {"hip", "knee"}, 2);
  const npz::NpzFile good = npz::decode_npz(encode_reference_npz(r), "g.npz");
  // Replaces (or with an empty array, removes) one key and decodes.
  auto with = [&](const std::string& key, const Array* replacement) {
    std::vector<NamedArray> a;
    bool found = false;
    for (const NamedArray& n : good.arrays) {
      if (n.key == key) {
        found = true;
        if (replacement) a.push_back({key, *replacement, 0});
      } else {
        a.push_back(n);
      }
    }
    if (!found && replacement) a.push_back({key, *replacement, 0});
    return [bytes = npz::encode_npz(a)] { decode_reference_npz(bytes, "bad.npz"); };
  };
  std::vector<double> q = good.find("joint_pos")->to_doubles();
  test::expect_input_error(with("fps", nullptr), {"bad.npz [fps.npy]", "missing required array 'fps'"});
  const Array zero_fps = Array::from_doubles({1}, {0.0});
  test::expect_input_error(with("fps", &zero_fps), {"bad.npz@0x", "[fps.npy]", "not between 1 and 10000 Hz"});
  test::expect_input_error(with("joint_pos", nullptr), {"missing required array 'joint_pos'"});
  const Array flat = Array::from_doubles({q.size()}, q);
  test::expect_input_error(with("joint_pos", &flat), {"[joint_pos.npy]", "expected shape (T, J)"});
  std::vector<double> q_nan = q;
  q_nan[2 * 5 + 1] = std::nan("");
  const Array nan_q = Array::from_doubles({8, 2}, q_nan);
  test::expect_input_error(with("joint_pos", &nan_q), {"bad.npz [joint_pos] frame 5 joint knee", "NaN"});
  const Array names3 = Array::from_strings({3}, {"a", "b", "c"});
  test::expect_input_error(with("joint_names", &names3), {"[joint_names.npy]", "shape (3,) where (2,) is expected"});
  const Array names_num = Array::from_doubles({2}, {1, 2});
  test::expect_input_error(with("joint_names", &names_num), {"[joint_names.npy]", "string array"});
  test::expect_input_error(with("root_quat_w", nullptr), {"[root_quat_w.npy]", "come together"});
  std::vector<double> quat = good.find("root_quat_w")->to_doubles();
  quat[4 * 3] = 3;
  const Array bad_quat = Array::from_doubles({8, 4}, quat);
  test::expect_input_error(with("root_quat_w", &bad_quat), {"bad.npz [root_quat_w] frame 3", "unit quaternion"});
  const Array short_pos = Array::from_doubles({7, 3}, std::vector<double>(21, 0.0));
  test::expect_input_error(with("root_pos_w", &short_pos), {"[root_pos_w.npy]", "shape (7, 3) where (8, 3) is expected"});
  const Array contacts2 = Array::from_ints({8, 2}, {0, 1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, DType::Int64);
  test::expect_input_error(with("contacts", &contacts2), {"bad.npz [contacts] frame 1 left", "not 0 or 1"});
  std::vector<double> times(8);
  for (int k = 0; k < 8; ++k) times[static_cast<std::size_t>(k)] = k == 4 ? 0.0 : k / 30.0;
  const Array t_bad = Array::from_doubles({8}, times);
  test::expect_input_error(with("time_s", &t_bad), {"[time_s.npy]", "not increasing at index 4"});
  const Array body_pos = Array::from_doubles({8, 1, 3}, std::vector<double>(24, 0.0));
  test::expect_input_error(with("body_pos_w", &body_pos), {"[body_quat_w.npy]", "need both"});
}

}  // namespace
}  // namespace rt
