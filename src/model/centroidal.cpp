#include "retarget/model/centroidal.hpp"

#include <algorithm>
#include <vector>

#include <mujoco/mujoco.h>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

CentroidalMomentum centroidal_momentum(const RobotModel& model, RobotData& data, const VecXCRef& q, const VecXCRef& v) {
  RT_DEMAND(q.size() == model.nq() && v.size() == model.nv(), "centroidal_momentum: q or v has the wrong size");
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  mju_copy(d->qpos, q.data(), m->nq);
  mju_copy(d->qvel, v.data(), m->nv);
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_comVel(m, d);
  mj_subtreeVel(m, d);
  const int b = model.root_body();
  CentroidalMomentum out;
  out.com_W = Eigen::Map<const Vec3>(d->subtree_com + 3 * b);
  out.linear_W = m->body_subtreemass[b] * Eigen::Map<const Vec3>(d->subtree_linvel + 3 * b);
  out.angular_com_W = Eigen::Map<const Vec3>(d->subtree_angmom + 3 * b);
  return out;
}

Matrix6X centroidal_momentum_matrix(const RobotModel& model, const RobotData& data) {
  const mjModel* m = model.mj();
  const mjData* d = data.mj();
  const int nb = m->nbody, tree = m->body_rootid[model.root_body()];
  // Composite inertias of the subtrees: MuJoCo's com-based inertias are all about the tree's COM,
  // so a subtree's is the plain sum of its bodies' (children have larger indices than parents).
  std::vector<double> crb(static_cast<std::size_t>(10 * nb), 0.0);
  for (int b = 1; b < nb; ++b)
    if (m->body_rootid[b] == tree) std::copy(d->cinert + 10 * b, d->cinert + 10 * b + 10, crb.begin() + 10 * b);
  for (int b = nb - 1; b > tree; --b)
    if (m->body_rootid[b] == tree)
      for (int k = 0; k < 10; ++k) crb[static_cast<std::size_t>(10 * m->body_parentid[b] + k)] += crb[static_cast<std::size_t>(10 * b + k)];
  Matrix6X A = Matrix6X::Zero(6, m->nv);
  for (int j = 0; j < m->nv; ++j) {
    const int b = m->dof_bodyid[j];
    if (m->body_rootid[b] != tree) continue;
    // Spatial inertia (I about the origin: xx yy zz xy xz yz; h = m (c_b − o); m) times the
    // motion axis (ω; v at the origin): angular I ω + h × v, linear m v + ω × h.
    const double* I = crb.data() + 10 * b;
    const double* s = d->cdof + 6 * j;
    const Vec3 w(s[0], s[1], s[2]), v(s[3], s[4], s[5]), h(I[6], I[7], I[8]);
    Mat3 Io;
    Io << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
    A.col(j).head<3>() = Io * w + h.cross(v);
    A.col(j).tail<3>() = I[9] * v + w.cross(h);
  }
  return A;
}

MatX centroidal_angular_matrix(const RobotModel& model, const RobotData& data) {
  return centroidal_momentum_matrix(model, data).topRows<3>();
}

Vec3 half_frame_angular_momentum(const RobotModel& model, const MatX& A_L_a, const MatX& A_L_b, const VecXCRef& q_a,
                                 const VecXCRef& q_b, double dt_s) {
  const VecX v = difference(model, q_a, q_b, dt_s);
  return 0.5 * (A_L_a * v + A_L_b * v);
}

ZmpSample zmp_sample(const Vec3& com_before_W, const Vec3& com_W, const Vec3& com_after_W, const Vec3& L_before,
                     const Vec3& L_after, double mass_kg, double fps) {
  const Vec3 acc = (com_after_W - 2 * com_W + com_before_W) * fps * fps;
  const Vec3 dL = (L_after - L_before) * fps;
  ZmpSample out;
  out.vertical_accel_raw = kGravity + acc.z();
  out.vertical_accel = std::max(out.vertical_accel_raw, kZmpMinSupport_g * kGravity);
  out.zmp_W = Vec2(com_W.x() - (com_W.z() * acc.x() + dL.y() / mass_kg) / out.vertical_accel,
                   com_W.y() - (com_W.z() * acc.y() - dL.x() / mass_kg) / out.vertical_accel);
  return out;
}

MultibodyZmp multibody_zmp(const RobotModel& model, RobotData& data, const MatX& q, double fps) {
  const int T = static_cast<int>(q.cols());
  RT_DEMAND(q.rows() == model.nq() && T > 0 && fps > 0, "multibody_zmp: bad motion");
  const double mass = model.mj()->body_subtreemass[model.root_body()];
  Mat3X com(3, T), L_half(3, std::max(T - 1, 0));
  MatX A_prev;
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, q.col(f));
    com.col(f) = com_position(model, data);
    MatX A = centroidal_angular_matrix(model, data);
    if (f > 0) L_half.col(f - 1) = half_frame_angular_momentum(model, A_prev, A, q.col(f - 1), q.col(f), 1.0 / fps);
    A_prev = std::move(A);
  }
  MultibodyZmp out;
  out.com_W = com;
  out.zmp_W.resize(2, T);
  out.zmp_gain_s2.resize(T);
  out.vertical_accel_mps2.setConstant(T, kGravity);
  for (int f = 0; f < T; ++f) {
    const int i = std::clamp(f, 1, std::max(T - 2, 1));  // ends reuse their neighbour's derivatives
    const Vec3& c = com.col(f);
    if (T < 3) {
      out.zmp_W.col(f) = c.head<2>();
      out.zmp_gain_s2[f] = c.z() / kGravity;
      continue;
    }
    const ZmpSample s = zmp_sample(com.col(i - 1), com.col(i), com.col(i + 1), L_half.col(i - 1), L_half.col(i), mass, fps);
    // An end frame takes its neighbour's ZMP offset from the COM, at its own COM.
    out.zmp_W.col(f) = c.head<2>() + (s.zmp_W - com.col(i).head<2>());
    out.zmp_gain_s2[f] = c.z() / s.vertical_accel;
    out.vertical_accel_mps2[f] = s.vertical_accel_raw;
  }
  return out;
}

}  // namespace rt
