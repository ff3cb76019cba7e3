#include "retarget/model/centroidal.hpp"

#include <algorithm>

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

MatX centroidal_angular_matrix(const RobotModel& model, const RobotData& data) {
  const mjModel* m = model.mj();
  // mj_jacBodyCom only uses mjData's scratch stack: the cached kinematics are not modified.
  mjData* d = const_cast<mjData*>(data.mj());
  const int nv = m->nv, root = model.root_body();
  const Vec3 c = Eigen::Map<const Vec3>(d->subtree_com + 3 * root);
  MatXr jp(3, nv), jr(3, nv);
  MatX A = MatX::Zero(3, nv);
  for (int b = 1; b < m->nbody; ++b) {
    if (!(m->body_mass[b] > 0) || m->body_rootid[b] != m->body_rootid[root]) continue;
    mj_jacBodyCom(m, d, jp.data(), jr.data(), b);
    const Vec3 r = Eigen::Map<const Vec3>(d->xipos + 3 * b) - c;
    Mat3 skew;
    skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);
    const Vec3 I(m->body_inertia[3 * b], m->body_inertia[3 * b + 1], m->body_inertia[3 * b + 2]);
    A.noalias() += m->body_mass[b] * skew * jp + (R * I.asDiagonal() * R.transpose()) * jr;
  }
  return A;
}

MultibodyZmp multibody_zmp(const RobotModel& model, RobotData& data, const MatX& q, double fps) {
  const int T = static_cast<int>(q.cols());
  RT_DEMAND(q.rows() == model.nq() && T > 0 && fps > 0, "multibody_zmp: bad motion");
  const double mass = model.mj()->body_subtreemass[model.root_body()];
  Mat3X com(3, T), L(3, T);
  for (int f = 0; f < T; ++f) {
    const int a = std::max(f - 1, 0), b = std::min(f + 1, T - 1);
    const VecX v = b > a ? difference(model, q.col(a), q.col(b), (b - a) / fps) : VecX::Zero(model.nv());
    const CentroidalMomentum h = centroidal_momentum(model, data, q.col(f), v);
    com.col(f) = h.com_W;
    L.col(f) = h.angular_com_W;
  }
  MultibodyZmp out;
  out.com_W = com;
  out.zmp_W.resize(2, T);
  out.zmp_gain_s2.resize(T);
  for (int f = 0; f < T; ++f) {
    const int i = std::clamp(f, 1, std::max(T - 2, 1));  // ends reuse their neighbour's derivatives
    Vec3 acc = Vec3::Zero(), dL = Vec3::Zero();
    if (T >= 3) {
      acc = (com.col(i + 1) - 2 * com.col(i) + com.col(i - 1)) * fps * fps;
      dL = (L.col(i + 1) - L.col(i - 1)) * (0.5 * fps);
    }
    const double fz = std::max(kGravity + acc.z(), 0.1 * kGravity);  // a robot in free fall has no ZMP
    const Vec3& c = com.col(f);
    out.zmp_W(0, f) = c.x() - (c.z() * acc.x() + dL.y() / mass) / fz;
    out.zmp_W(1, f) = c.y() - (c.z() * acc.y() - dL.x() / mass) / fz;
    out.zmp_gain_s2[f] = c.z() / fz;
  }
  return out;
}

}  // namespace rt
