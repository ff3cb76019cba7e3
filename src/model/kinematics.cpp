#include "retarget/model/kinematics.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "retarget/core/error.hpp"
#include "retarget/model/centroidal.hpp"

namespace rt {

namespace {

using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

const Link& checked_link(const RobotModel& model, int link) {
  RT_DEMAND(link >= 0 && link < static_cast<int>(model.links().size()), "link index out of range");
  const Link& l = model.links()[static_cast<std::size_t>(link)];
  RT_DEMAND(l.body >= 0, "link has no MuJoCo body");
  return l;
}

Iso3 body_pose(const mjData* d, int body) {
  Iso3 X = Iso3::Identity();
  X.translation() = Eigen::Map<const Vec3>(d->xpos + 3 * body);
  X.linear() = Eigen::Map<const RowMat3>(d->xmat + 9 * body);
  return X;
}

// The last dof whose velocity moves `body` (its own, or its nearest ancestor's with dofs); the
// dofs moving it are this one and its dof_parentid chain. -1 for a body welded to the world.
int last_dof_moving(const mjModel* m, int body) {
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  return body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1;
}

}  // namespace

void update_kinematics(const RobotModel& model, RobotData& data, const VecXCRef& q) {
  RT_DEMAND(q.size() == model.nq(), "q has the wrong size");
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  mju_copy(d->qpos, q.data(), m->nq);
  mj_kinematics(m, d);
  mj_comPos(m, d);
}

void update_dynamics(const RobotModel& model, RobotData& data, const VecXCRef& q, const VecXCRef& v) {
  RT_DEMAND(q.size() == model.nq() && v.size() == model.nv(), "q or v has the wrong size");
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  mju_copy(d->qpos, q.data(), m->nq);
  mju_copy(d->qvel, v.data(), m->nv);
  // The position and velocity stages of mj_forward that the controller needs; collision
  // detection and the constraint solver are skipped (the controller has its own contact model).
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_crb(m, d);
  mj_factorM(m, d);
  mj_comVel(m, d);
  mj_rne(m, d, 0, d->qfrc_bias);
}

void assign_dynamics(const RobotModel& model, RobotData& data, const mjData& source) {
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  // What update_dynamics writes: its inputs, then the results of mj_kinematics, mj_comPos, mj_crb,
  // mj_factorM, mj_comVel and mj_rne.
  mju_copy(d->qpos, source.qpos, m->nq);
  mju_copy(d->qvel, source.qvel, m->nv);
  mju_copy(d->xpos, source.xpos, 3 * m->nbody);
  mju_copy(d->xquat, source.xquat, 4 * m->nbody);
  mju_copy(d->xmat, source.xmat, 9 * m->nbody);
  mju_copy(d->xipos, source.xipos, 3 * m->nbody);
  mju_copy(d->ximat, source.ximat, 9 * m->nbody);
  mju_copy(d->xanchor, source.xanchor, 3 * m->njnt);
  mju_copy(d->xaxis, source.xaxis, 3 * m->njnt);
  mju_copy(d->geom_xpos, source.geom_xpos, 3 * m->ngeom);
  mju_copy(d->geom_xmat, source.geom_xmat, 9 * m->ngeom);
  mju_copy(d->site_xpos, source.site_xpos, 3 * m->nsite);
  mju_copy(d->site_xmat, source.site_xmat, 9 * m->nsite);
  mju_copy(d->subtree_com, source.subtree_com, 3 * m->nbody);
  mju_copy(d->cinert, source.cinert, 10 * m->nbody);
  mju_copy(d->cdof, source.cdof, 6 * m->nv);
  mju_copy(d->crb, source.crb, 10 * m->nbody);
  mju_copy(d->qM, source.qM, m->nM);
  mju_copy(d->qLD, source.qLD, m->nM);
  mju_copy(d->qLDiagInv, source.qLDiagInv, m->nv);
  mju_copy(d->qLDiagSqrtInv, source.qLDiagSqrtInv, m->nv);
  mju_copy(d->cvel, source.cvel, 6 * m->nbody);
  mju_copy(d->cdof_dot, source.cdof_dot, 6 * m->nv);
  mju_copy(d->qfrc_bias, source.qfrc_bias, m->nv);
}

Iso3 link_pose(const RobotModel& model, const RobotData& data, int link) {
  const Link& l = checked_link(model, link);
  return body_pose(data.mj(), l.body) * l.X_B_L;
}

Vec3 link_point(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L) {
  return link_pose(model, data, link) * p_L;
}

MatX link_jacobian(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L) {
  const Link& l = checked_link(model, link);
  const int nv = model.nv();
  const Vec3 p_W = link_point(model, data, link, p_L);
  MatXr jp(3, nv), jr(3, nv);
  mj_jac(model.mj(), data.mj(), jp.data(), jr.data(), p_W.data(), l.body);
  MatX J(6, nv);
  J.topRows(3) = jp;
  J.bottomRows(3) = jr;
  return J;
}

Vec3 com_position(const RobotModel& model, const RobotData& data) {
  return Eigen::Map<const Vec3>(data.mj()->subtree_com + 3 * model.root_body());
}

MatX com_jacobian(const RobotModel& model, const RobotData& data) {
  // The linear rows of the centroidal momentum matrix over the mass: one pass over the bodies and
  // dofs, where mj_jacSubtreeCom takes a body Jacobian per body.
  return centroidal_momentum_matrix(model, data).bottomRows<3>() / model.mj()->body_subtreemass[model.root_body()];
}

MatX mass_matrix(const RobotModel& model, const RobotData& data) {
  MatXr M(model.nv(), model.nv());
  mj_fullM(model.mj(), M.data(), data.mj()->qM);
  return M;
}

VecX bias_forces(const RobotModel& model, const RobotData& data) {
  return Eigen::Map<const VecX>(data.mj()->qfrc_bias, model.nv());
}

Vec6 link_jdot_v(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L) {
  const Link& l = checked_link(model, link);
  const mjModel* m = model.mj();
  const mjData* d = data.mj();
  // MuJoCo 2.2.2 has no mj_jacDot. With q̈ = 0 the spatial acceleration of a body is the sum of
  // cdof_dot·q̇ over the dofs that move it (the forward pass of mj_rne / mj_rnePostConstraint
  // without gravity), in MuJoCo's com-based frame ([angular; linear] at the root's subtree COM).
  Vec6 cacc = Vec6::Zero();
  for (int j = last_dof_moving(m, l.body); j >= 0; j = m->dof_parentid[j])
    cacc += Eigen::Map<const Vec6>(d->cdof_dot + 6 * j) * d->qvel[j];
  const Vec3 p_W = link_point(model, data, link, p_L);
  const mjtNum* com = d->subtree_com + 3 * m->body_rootid[l.body];
  mjtNum vel[6], acc[6];
  // Spatial velocity and acceleration moved to the point.
  mju_transformSpatial(vel, d->cvel + 6 * l.body, 0, p_W.data(), com, nullptr);
  mju_transformSpatial(acc, cacc.data(), 0, p_W.data(), com, nullptr);
  const Vec3 omega(vel[0], vel[1], vel[2]);
  const Vec3 v_p(vel[3], vel[4], vel[5]);
  // Classical acceleration of the body-fixed point = spatial acceleration + ω × v_p (this carries
  // the ω × (ω × r) term of the offset r from the body origin).
  Vec6 out;
  out << Vec3(acc[3], acc[4], acc[5]) + omega.cross(v_p), Vec3(acc[0], acc[1], acc[2]);
  return out;
}

std::vector<int> link_dof_chain(const RobotModel& model, int link) {
  const Link& l = checked_link(model, link);
  const mjModel* m = model.mj();
  std::vector<int> dofs;
  for (int j = last_dof_moving(m, l.body); j >= 0; j = m->dof_parentid[j]) dofs.push_back(j);
  std::reverse(dofs.begin(), dofs.end());
  return dofs;
}

void solve_mass_matrix(const RobotModel& model, const RobotData& data, Eigen::Ref<MatXr> X) {
  const mjModel* m = model.mj();
  const mjData* d = data.mj();
  const int nv = m->nv;
  RT_DEMAND(X.rows() == nv, "solve_mass_matrix: right-hand sides need nv rows");
  // mj_factorM leaves M = Lᵀ D L in qLD: per dof i, D(i) at dof_Madr[i], then L(i, j) for the
  // ancestors j of i, nearest first (L is unit lower triangular and zero elsewhere).
  const mjtNum* LD = d->qLD;
  const Eigen::Index n = X.cols(), ld = X.outerStride();
  double* x = X.data();
  // row_a -= l · row_b over the n right-hand sides: the inner loop the compiler vectorises.
  const auto axpy = [n](double* __restrict a, const double* __restrict b, double l) {
    for (Eigen::Index k = 0; k < n; ++k) a[k] -= l * b[k];
  };
  // X ← L⁻ᵀ X, leaves first.
  for (int i = nv - 1; i >= 0; --i) {
    int adr = m->dof_Madr[i] + 1;
    for (int j = m->dof_parentid[i]; j >= 0; j = m->dof_parentid[j]) axpy(x + j * ld, x + i * ld, LD[adr++]);
  }
  // X ← D⁻¹ X, then X ← L⁻¹ X, root first.
  for (int i = 0; i < nv; ++i) {
    double* x_i = x + i * ld;
    const double d_inv = d->qLDiagInv[i];
    for (Eigen::Index k = 0; k < n; ++k) x_i[k] *= d_inv;
    int adr = m->dof_Madr[i] + 1;
    for (int j = m->dof_parentid[i]; j >= 0; j = m->dof_parentid[j]) axpy(x_i, x + j * ld, LD[adr++]);
  }
}

VecX integrate(const RobotModel& model, const VecXCRef& q, const VecXCRef& v, double dt) {
  RT_DEMAND(q.size() == model.nq() && v.size() == model.nv(), "q or v has the wrong size");
  VecX out = q;
  mj_integratePos(model.mj(), out.data(), v.data(), dt);
  return out;
}

VecX difference(const RobotModel& model, const VecXCRef& q1, const VecXCRef& q2, double dt) {
  RT_DEMAND(q1.size() == model.nq() && q2.size() == model.nq(), "q has the wrong size");
  RT_DEMAND(dt > 0, "dt must be positive");
  VecX v(model.nv());
  mj_differentiatePos(model.mj(), v.data(), dt, q1.data(), q2.data());
  return v;
}

std::array<Mat3, 2> sole_frames_in_links(const RobotModel& model, RobotData& data) {
  VecX q0 = VecX::Zero(model.nq());
  q0[3] = 1;
  update_kinematics(model, data, q0);
  std::array<Mat3, 2> R;
  for (int foot = 0; foot < 2; ++foot) R[static_cast<std::size_t>(foot)] = model.soles()[static_cast<std::size_t>(foot)].R_L_S;
  return R;
}

double lowest_sole_corner_z(const RobotModel& model, const RobotData& data, int foot) {
  const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
  const Iso3 X = link_pose(model, data, sole.link);
  double z = INFINITY;
  for (const Vec3& c : sole.corners_L()) z = std::min(z, (X * c).z());
  return z;
}

}  // namespace rt
