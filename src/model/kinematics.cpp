#include "retarget/model/kinematics.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "retarget/core/error.hpp"

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
  MatXr jp(3, model.nv());
  // mj_jacSubtreeCom only uses mjData's scratch stack: the cached results are not modified.
  mj_jacSubtreeCom(model.mj(), const_cast<mjData*>(data.mj()), jp.data(), model.root_body());
  return jp;
}

MatX mass_matrix(const RobotModel& model, const RobotData& data) {
  MatXr M(model.nv(), model.nv());
  mj_fullM(model.mj(), M.data(), data.mj()->qM);
  return M;
}

VecX bias_forces(const RobotModel& model, const RobotData& data) {
  return Eigen::Map<const VecX>(data.mj()->qfrc_bias, model.nv());
}

std::vector<Vec6> links_jdot_v(const RobotModel& model, RobotData& data, const std::vector<int>& links,
                               const std::vector<Vec3>& p_L) {
  RT_DEMAND(links.size() == p_L.size(), "links_jdot_v: one point per link");
  const mjModel* m = model.mj();
  mjData* d = data.mj();
  // MuJoCo 2.2.2 has no mj_jacDot: the body accelerations with q̈ = 0 are exactly J̇·v
  // (dependencies.md §5). cacc carries a -gravity offset, added back below.
  std::vector<mjtNum> saved_qacc(d->qacc, d->qacc + m->nv);
  mju_zero(d->qacc, m->nv);
  mj_rnePostConstraint(m, d);
  std::vector<Vec6> out;
  out.reserve(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    const Link& l = checked_link(model, links[i]);
    const Vec3 p_W = link_point(model, data, links[i], p_L[i]);
    const mjtNum* com = d->subtree_com + 3 * m->body_rootid[l.body];
    mjtNum vel[6], acc[6];
    // Spatial velocity and acceleration (MuJoCo order [angular; linear]) moved to the point.
    mju_transformSpatial(vel, d->cvel + 6 * l.body, 0, p_W.data(), com, nullptr);
    mju_transformSpatial(acc, d->cacc + 6 * l.body, 0, p_W.data(), com, nullptr);
    const Vec3 omega(vel[0], vel[1], vel[2]);
    const Vec3 v_p(vel[3], vel[4], vel[5]);
    // Classical acceleration of the body-fixed point = spatial acceleration + ω × v_p (this carries
    // the ω × (ω × r) term of the offset r from the body origin).
    const Vec3 a_p = Vec3(acc[3], acc[4], acc[5]) + omega.cross(v_p) + Eigen::Map<const Vec3>(m->opt.gravity);
    Vec6 j;
    j << a_p, Vec3(acc[0], acc[1], acc[2]);
    out.push_back(j);
  }
  mju_copy(d->qacc, saved_qacc.data(), m->nv);
  return out;
}

Vec6 link_jdot_v(const RobotModel& model, RobotData& data, int link, const Vec3& p_L) {
  return links_jdot_v(model, data, {link}, {p_L}).front();
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
  for (int foot = 0; foot < 2; ++foot)
    R[static_cast<std::size_t>(foot)] = link_pose(model, data, model.soles()[static_cast<std::size_t>(foot)].link).linear().transpose();
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
