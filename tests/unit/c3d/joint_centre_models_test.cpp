// Joint-centre models, rigid-cluster tools and gap filling, on geometry with known answers.

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "retarget/motion/c3d/joint_centre_models.hpp"
#include "retarget/motion/c3d/landmark_gaps.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"
#include "retarget/motion/c3d/rigid_cluster.hpp"

namespace rt {
namespace {

TEST(JointCentreModels, MarkerNames) {
  EXPECT_EQ(normalise_marker_name("Matt:RASI"), "RASI");
  EXPECT_EQ(normalise_marker_name("ANTO_M:lasi "), "LASI");
  EXPECT_EQ(normalise_marker_name("L_IAS"), "L_IAS");
  EXPECT_EQ(normalise_marker_name(""), "");
}

TEST(JointCentreModels, PelvisFrameAndRegressions) {
  // ASIS 0.24 m apart, PSIS midpoint 0.16 m behind and 0.02 m higher (tilted pelvis).
  const auto pf = pelvis_frame(Vec3(0.1, 0.12, 1.0), Vec3(0.1, -0.12, 1.0), Vec3(-0.06, 0.0, 1.02));
  ASSERT_TRUE(pf);
  EXPECT_NEAR(pf->pelvis_width_m, 0.24, 1e-12);
  EXPECT_NEAR(pf->pelvis_depth_m, std::hypot(0.16, 0.02), 1e-12);
  EXPECT_TRUE(pf->X_F_P.translation().isApprox(Vec3(0.1, 0, 1.0)));
  EXPECT_NEAR(pf->X_F_P.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE((pf->X_F_P.linear().col(1)).isApprox(Vec3::UnitY()));
  EXPECT_FALSE(pelvis_frame(Vec3::Zero(), Vec3::Zero(), Vec3(1, 0, 0)));

  // Harrington 2007: x = -0.24 PD - 9.9 mm, z = -0.30 PW - 10.9 mm, lateral = 0.33 PW + 7.3 mm.
  const Vec3 h = hip_centre_harrington(0.24, 0.16, true);
  EXPECT_NEAR(h.x(), -0.24 * 0.16 - 0.0099, 1e-12);
  EXPECT_NEAR(h.y(), 0.33 * 0.24 + 0.0073, 1e-12);
  EXPECT_NEAR(h.z(), -0.30 * 0.24 - 0.0109, 1e-12);
  EXPECT_TRUE(hip_centre_harrington(0.24, 0.16, false).isApprox(Vec3(h.x(), -h.y(), h.z())));

  // Davis 1991 / Plug-in Gait, checked against a hand computation for LL 940 mm, d_AT 72.512 mm,
  // inter-ASIS 227.043 mm, marker radius 7 mm: C = 92.8 mm.
  const Vec3 d = hip_centre_davis(0.940, 0.072512, 0.227043, 0.007, true);
  const double c = 0.0928;
  EXPECT_NEAR(d.x(), c * std::cos(0.5) * std::sin(0.314) - 0.079512 * std::cos(0.314), 1e-9);
  EXPECT_NEAR(d.y(), 0.1135215 - c * std::sin(0.5), 1e-9);
  EXPECT_NEAR(d.z(), -c * std::cos(0.5) * std::cos(0.314) - 0.079512 * std::sin(0.314), 1e-9);
  EXPECT_GT(d.y(), 0.06);  // about 70 mm lateral of the midline, 50 mm back, 100 mm down
  EXPECT_LT(d.x(), -0.04);
  EXPECT_LT(d.z(), -0.09);
  // Unknown ASIS-trochanter distance: Davis' own regression 0.1288 LL - 48.56 mm.
  EXPECT_TRUE(hip_centre_davis(0.940, 0, 0.227043, 0.007, true)
                  .isApprox(hip_centre_davis(0.940, 0.1288 * 0.940 - 0.04856, 0.227043, 0.007, true)));
  EXPECT_TRUE(hip_centre_bell(0.25, false).isApprox(Vec3(-0.0475, -0.09, -0.075)));
}

TEST(JointCentreModels, ChordFunction) {
  const Vec3 hip(0, 0.1, 0.9), knee_marker(0.0, 0.16, 0.5), wand(0.02, 0.19, 0.7);
  const auto j = chord_joint_centre(hip, knee_marker, wand, 0.06);
  ASSERT_TRUE(j);
  EXPECT_NEAR((*j - knee_marker).norm(), 0.06, 1e-12);                     // offset from the marker
  EXPECT_NEAR((*j - knee_marker).dot(*j - hip), 0.0, 1e-12);               // right angle at J
  const Vec3 n = (knee_marker - hip).cross(wand - knee_marker);
  EXPECT_NEAR((*j - hip).dot(n), 0.0, 1e-12);                              // in the plane
  EXPECT_LT(j->y(), knee_marker.y());                                      // medial: away from the wand
  const auto toward = chord_joint_centre(hip, knee_marker, wand, 0.06, ChordSide::TowardPlaneMarker);
  EXPECT_GT(toward->y(), j->y());
  EXPECT_FALSE(chord_joint_centre(hip, knee_marker, hip + 0.5 * (knee_marker - hip), 0.06));  // wand on the line
  EXPECT_FALSE(chord_joint_centre(hip, knee_marker, wand, 1.0));  // offset longer than the segment
}

TEST(JointCentreModels, ElbowOnTheFlexionAxis) {
  // Left arm hanging at the side (+y is lateral), elbow flexed 90 degrees forward (+x).
  const Vec3 shoulder(0, 0.2, 1.4), ejc(0, 0.2, 1.1), wrist_mid(0.25, 0.2, 1.1);
  const double offset = 0.045;
  const Vec3 lateral_marker = ejc + Vec3(0, offset, 0);
  const auto j = elbow_joint_centre(shoulder, lateral_marker, wrist_mid, offset, true);
  ASSERT_TRUE(j);
  // Plug-in Gait takes the flexion-axis direction from the marker, not the joint centre: a few
  // millimetres of error by construction (matches Vicon's own outputs, see c3d_motion_test).
  EXPECT_LT((*j - ejc).norm(), 0.01);
  EXPECT_NEAR((*j - lateral_marker).norm(), offset, 1e-9);
  EXPECT_LT(j->y(), lateral_marker.y());  // medial
  // The right arm mirrored gives the mirrored centre.
  const Vec3 flip(1, -1, 1);
  const auto r = elbow_joint_centre(shoulder.cwiseProduct(flip), lateral_marker.cwiseProduct(flip),
                                    wrist_mid.cwiseProduct(flip), offset, false);
  ASSERT_TRUE(r);
  EXPECT_LT((*r - j->cwiseProduct(flip)).norm(), 1e-12);
  // A marker on the shoulder-wrist line defines no plane: returned as it is.
  EXPECT_TRUE(elbow_joint_centre(shoulder, ejc, Vec3(0, 0.2, 0.85), offset, true)->isApprox(ejc));
  EXPECT_FALSE(elbow_joint_centre(shoulder, shoulder, wrist_mid, offset, true));
}

Mat3X random_cluster(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  Mat3X p(3, n);
  for (int i = 0; i < n; ++i) p.col(i) = Vec3(u(rng), u(rng), u(rng));
  return p;
}

TEST(RigidCluster, FitRecoversTheMotion) {
  std::mt19937 rng(7);
  const Mat3X from = random_cluster(rng, 5);
  Iso3 x = Iso3::Identity();
  x.linear() = AngleAxis(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  x.translation() = Vec3(0.3, -1, 2);
  double rms = 1;
  const auto fit = fit_rigid_transform(from, x * from, 0.01, &rms);
  ASSERT_TRUE(fit);
  EXPECT_TRUE(fit->isApprox(x, 1e-9));
  EXPECT_LT(rms, 1e-12);
  // Against a reference Kabsch (Jacobi SVD) on noisy 3-, 4- and 6-marker clusters.
  std::normal_distribution<double> noise(0, 0.002);
  for (int trial = 0; trial < 200; ++trial) {
    Mat3X f = 0.2 * random_cluster(rng, 3 + trial % 4);
    f.leftCols<3>() += 0.1 * Mat3::Identity();  // a well-spread triangle plus small random offsets
    Iso3 y = Iso3::Identity();
    y.linear() = AngleAxis(0.03 * trial, Vec3(std::sin(trial), std::cos(trial), 0.3).normalized()).toRotationMatrix();
    Mat3X t = (y * f);
    for (Eigen::Index i = 0; i < t.cols(); ++i) t.col(i) += Vec3(noise(rng), noise(rng), noise(rng));
    const auto got = fit_rigid_transform(f, t);
    ASSERT_TRUE(got) << "trial " << trial;
    const Mat3X a = f.colwise() - Vec3(f.rowwise().mean());
    const Mat3X b = t.colwise() - Vec3(t.rowwise().mean());
    const Eigen::JacobiSVD<Mat3> svd(a * b.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 d = Mat3::Identity();
    d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
    const Mat3 expected = svd.matrixV() * d * svd.matrixU().transpose();
    EXPECT_LT((got->linear() - expected).norm(), 1e-6) << trial;
    EXPECT_NEAR(got->linear().determinant(), 1.0, 1e-9);
  }
  // Collinear markers fix no rotation.
  Mat3X line(3, 3);
  line << 0, 0.1, 0.2, 0, 0, 0, 0, 0, 0;
  EXPECT_FALSE(fit_rigid_transform(line, line));
}

// A ball joint at c between two rigid clusters moving through many orientations.
TEST(RigidCluster, ScoreFindsABallJoint) {
  std::mt19937 rng(11);
  const Mat3X a0 = random_cluster(rng, 4).colwise() + Vec3(0, 0, 0.25);
  const Mat3X b0 = random_cluster(rng, 4).colwise() + Vec3(0, 0, -0.25);
  const Vec3 c(0.01, -0.02, 0.0);
  MarkerTrajectories ms;
  ms.num_frames = 200;
  for (int i = 0; i < 8; ++i) {
    MarkerTrajectory m;
    m.p_F.resize(3, ms.num_frames);
    m.state.assign(static_cast<std::size_t>(ms.num_frames), SampleState::Measured);
    ms.markers.push_back(m);
  }
  std::normal_distribution<double> noise(0, 0.0005);
  for (int f = 0; f < ms.num_frames; ++f) {
    const double t = f * 0.05;
    Iso3 xa = Iso3::Identity(), xb = Iso3::Identity();
    xa.linear() = AngleAxis(0.3 * std::sin(t), Vec3::UnitZ()).toRotationMatrix();
    xa.translation() = Vec3(0.5 * t, 0.1 * std::cos(t), 0);
    // b rotates about the joint centre c (fixed in both reference configurations).
    const Mat3 rb = (AngleAxis(0.6 * std::sin(1.3 * t), Vec3::UnitX()) * AngleAxis(0.5 * std::cos(0.7 * t), Vec3::UnitY()))
                        .toRotationMatrix();
    xb.linear() = xa.linear() * rb;
    xb.translation() = xa * c - xb.linear() * c;
    for (int i = 0; i < 4; ++i) {
      ms.markers[static_cast<std::size_t>(i)].p_F.col(f) = xa * Vec3(a0.col(i)) + Vec3(noise(rng), noise(rng), noise(rng));
      ms.markers[static_cast<std::size_t>(i + 4)].p_F.col(f) = xb * Vec3(b0.col(i)) + Vec3(noise(rng), noise(rng), noise(rng));
    }
  }
  const ClusterPoses pa = track_cluster(ms, {0, 1, 2, 3});
  const ClusterPoses pb = track_cluster(ms, {4, 5, 6, 7});
  EXPECT_EQ(pa.valid_count(), 200);
  const auto j = score_joint_centre(pa, pb, Vec3::Zero(), Vec3::Zero());
  ASSERT_TRUE(j);
  // The reference is frame 0; map the true centre into it.
  const Vec3 c_ref = pa.X_F_S[0].inverse() * (Iso3(Eigen::Translation3d(0, 0.1, 0)) * c);
  EXPECT_LT((pa.X_F_S[0] * j->c_a - Iso3(Eigen::Translation3d(0, 0.1, 0)) * c).norm(), 0.003);
  EXPECT_LT(j->rms_m, 0.003);
  (void)c_ref;
}

TEST(RigidCluster, FillsAGapFromTheOtherMarkers) {
  std::mt19937 rng(3);
  const Mat3X shape = random_cluster(rng, 4);
  MarkerTrajectories ms;
  ms.num_frames = 50;
  for (int i = 0; i < 4; ++i) {
    MarkerTrajectory m;
    m.p_F.resize(3, 50);
    m.state.assign(50, SampleState::Measured);
    ms.markers.push_back(m);
  }
  std::vector<Iso3> poses;
  for (int f = 0; f < 50; ++f) {
    Iso3 x = Iso3::Identity();
    x.linear() = AngleAxis(0.05 * f, Vec3(0, 1, 1).normalized()).toRotationMatrix();
    x.translation() = Vec3(0.02 * f, 0, 0.01 * f);
    poses.push_back(x);
    for (int i = 0; i < 4; ++i) ms.markers[static_cast<std::size_t>(i)].p_F.col(f) = x * Vec3(shape.col(i));
  }
  for (int f = 10; f < 30; ++f) ms.markers[2].state[static_cast<std::size_t>(f)] = SampleState::Missing;
  for (int f = 45; f < 50; ++f) ms.markers[2].state[static_cast<std::size_t>(f)] = SampleState::Missing;  // trailing
  EXPECT_EQ(fill_from_rigid_cluster(ms, {0, 1, 2, 3}), 25);
  for (int f : {10, 20, 29, 47}) {
    EXPECT_EQ(ms.markers[2].state[static_cast<std::size_t>(f)], SampleState::Interpolated);
    EXPECT_LT((ms.markers[2].p_F.col(f) - poses[static_cast<std::size_t>(f)] * Vec3(shape.col(2))).norm(), 1e-9);
  }
  EXPECT_EQ(fill_from_rigid_cluster(ms, {0, 1, 2}), 0);  // a marker needs three others
}

TEST(LandmarkGaps, FillHoldAndSpan) {
  LandmarkTrack t;
  t.present = true;
  const int n = 40;
  t.p_W.resize(3, n);
  t.state.assign(n, SampleState::Measured);
  for (int f = 0; f < n; ++f) t.p_W.col(f) = Vec3(std::sin(0.1 * f), 0.5 * f, 1.0);
  for (int f : {0, 1, 10, 11, 12, 20, 21, 22, 23, 24, 25, 26, 27, 38, 39}) t.state[static_cast<std::size_t>(f)] = SampleState::Missing;
  const Mat3X truth = t.p_W;
  const GapReport r = fill_gaps(t, 4);
  EXPECT_TRUE(r.has_valid);
  EXPECT_EQ(r.filled_gaps, 1);
  EXPECT_EQ(r.filled_frames, 3);
  ASSERT_EQ(r.long_gaps.size(), 1u);
  EXPECT_EQ(r.long_gaps[0].begin, 20);
  EXPECT_EQ(r.long_gaps[0].end, 28);
  EXPECT_EQ(r.leading.length(), 2);
  EXPECT_EQ(r.trailing.begin, 38);
  for (int f : {10, 11, 12}) {
    EXPECT_EQ(t.state[static_cast<std::size_t>(f)], SampleState::Interpolated);
    EXPECT_LT((t.p_W.col(f) - truth.col(f)).norm(), 0.005);  // cubic Hermite on a smooth curve
  }
  EXPECT_EQ(t.p_W.col(0), truth.col(2));   // leading frames hold the first valid sample
  EXPECT_EQ(t.p_W.col(21), truth.col(19));  // long gap: nearest end
  EXPECT_EQ(t.p_W.col(26), truth.col(28));
  EXPECT_EQ(t.p_W.col(39), truth.col(37));

  HumanMotion m;
  m.num_frames = n;
  m[Landmark::Pelvis] = t;
  m[Landmark::LeftKnee] = t;
  m[Landmark::LeftKnee].state[5] = SampleState::Missing;
  for (int f = 0; f < 8; ++f) m[Landmark::LeftKnee].state[static_cast<std::size_t>(f)] = SampleState::Missing;
  const FrameGap span = common_valid_span(m, {Landmark::Pelvis, Landmark::LeftKnee, Landmark::Head});
  EXPECT_EQ(span.begin, 8);
  EXPECT_EQ(span.end, 38);
  trim_frames(m, span.begin, span.end);
  EXPECT_EQ(m.num_frames, 30);
  EXPECT_EQ(m[Landmark::Pelvis].p_W.cols(), 30);
  EXPECT_EQ(m[Landmark::Pelvis].state.size(), 30u);
}

}  // namespace
}  // namespace rt
