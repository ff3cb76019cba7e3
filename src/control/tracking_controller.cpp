#include "retarget/control/tracking_controller.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"

namespace rt {

namespace {

Mat3 skew(const Vec3& a) {
  Mat3 S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

// Rotation vector (W) taking R to R_ref: log(R_ref Rᵀ).
Vec3 rotation_error(const Mat3& R_ref, const Mat3& R) {
  const AngleAxis aa(R_ref * R.transpose());
  return aa.angle() * aa.axis();
}

// Maps (force; moment about the world origin) to the horizontal moment about a point r on the floor:
// N − r × F, x and y rows (eq. 11 with the sign noted in the header).
Eigen::Matrix<double, 2, 6> moment_about(const Vec2& r) {
  Eigen::Matrix<double, 2, 6> C = Eigen::Matrix<double, 2, 6>::Zero();
  C(0, 2) = -r.y();
  C(0, 3) = 1;
  C(1, 2) = r.x();
  C(1, 4) = 1;
  return C;
}

// Eq. (10): wrench (f; n) applied at r -> (force; moment about the world origin).
Mat6 wrench_to_origin(const Vec3& r) {
  Mat6 T = Mat6::Identity();
  T.block<3, 3>(3, 0) = skew(r);
  return T;
}

}  // namespace

TrackingController::TrackingController(const RobotModel& model, TrackingOptions options)
    : model_(&model), options_(std::move(options)) {
  const int nv = model.nv(), nu = model.nu();
  auto per_joint = [&](const VecX& given, double fallback, const char* what) {
    if (given.size() == 0) return VecX::Constant(nu, fallback).eval();
    if (given.size() != nu)
      throw InputError(std::string("tracking controller: ") + what + " has " + std::to_string(given.size()) +
                       " entries, expected " + std::to_string(nu));
    return given;
  };
  kp_.resize(nv);
  kd_.resize(nv);
  kp_.head<6>().setConstant(options_.root_kp);
  kd_.head<6>().setConstant(options_.root_kd);
  kp_.tail(nu) = per_joint(options_.kp_joint, options_.kp, "kp_joint");
  kd_.tail(nu) = per_joint(options_.kd_joint, options_.kd, "kd_joint");
  const TrackingWeights& w = options_.weights;
  w_q_.resize(nv);
  w_q_.head<3>().setConstant(w.root_linear);
  w_q_.segment<3>(3).setConstant(w.root_angular);
  w_q_.tail(nu).setConstant(w.joint);
  std::vector<int> dofs = link_dof_chain(model, model.soles()[0].link);
  for (int j : link_dof_chain(model, model.soles()[1].link)) dofs.push_back(j);
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  feet_dofs_ = std::move(dofs);
  const ContactConstraintOptions& c = options_.contact;
  friction_ = c.friction > 0 ? c.friction : model.config().simulation.friction;
  if (c.enabled && !(friction_ > 0 && c.friction_margin > 0 && c.cop_margin > 0 && c.cop_margin <= 1 &&
                     c.min_normal_force_n >= 0))
    throw InputError("tracking controller: contact limits need friction > 0, friction_margin > 0, cop_margin in (0, 1] "
                     "and min_normal_force_n >= 0");
}

void TrackingController::foot_weights(const std::array<bool, 2>& contact, VecX& w_c) const {
  const TrackingWeights& w = options_.weights;
  w_c.resize(12);
  for (int foot = 0; foot < 2; ++foot) {
    const bool stance = contact[static_cast<std::size_t>(foot)];
    w_c.segment<3>(6 * foot).setConstant(stance ? w.stance_foot : w.foot_linear);
    w_c.segment<3>(6 * foot + 3).setConstant(stance ? w.stance_foot : w.foot_angular);
  }
}

void TrackingController::contact_limits(TrackingProblem& p) const {
  const ContactConstraintOptions& o = options_.contact;
  const int nc = static_cast<int>(p.contact_feet.size());
  if (!o.enabled || nc == 0) {
    p.C_contact.resize(0, p.nf);
    p.d_contact.resize(0);
    return;
  }
  constexpr int kRows = 17;
  // Optional rows f_z ≤ f_max (−f_z ≥ −f_max) after the per-foot blocks.
  int capped = 0;
  for (int f : p.contact_feet) capped += std::isfinite(p.max_normal_force_n[static_cast<std::size_t>(f)]);
  p.C_contact.setZero(kRows * nc + capped, p.nf);
  p.d_contact.setZero(kRows * nc + capped);
  for (int i = 0, row = kRows * nc; i < nc; ++i) {
    const double f_max = p.max_normal_force_n[static_cast<std::size_t>(p.contact_feet[static_cast<std::size_t>(i)])];
    if (!std::isfinite(f_max)) continue;
    p.C_contact.block<1, 3>(row, 6 * i) = -p.R_contact_W[static_cast<std::size_t>(i)].col(2).transpose();
    p.d_contact[row] = -std::max(f_max, o.min_normal_force_n);
    ++row;
  }
  const double mu = o.friction_margin * friction_ / std::sqrt(2.0);
  for (int i = 0; i < nc; ++i) {
    const Sole& sole = model_->soles()[static_cast<std::size_t>(p.contact_feet[static_cast<std::size_t>(i)])];
    const Mat3& R = p.R_contact_W[static_cast<std::size_t>(i)];
    const Eigen::RowVector3d ex = R.col(0).transpose(), ey = R.col(1).transpose(), ez = R.col(2).transpose();
    const double half_l = 0.5 * o.cop_margin * sole.size_m.x(), half_w = 0.5 * o.cop_margin * sole.size_m.y();
    auto block = p.C_contact.block(kRows * i, 6 * i, kRows, 6);
    // Rows act on (f; n) in W; sole-frame components are R.col(k)ᵀ f and R.col(k)ᵀ n.
    block.row(0) << ez, 0, 0, 0;                    // f_z ≥ f_min
    p.d_contact[kRows * i] = o.min_normal_force_n;
    block.row(1) << mu * ez - ex, 0, 0, 0;          // |f_x| ≤ μ' f_z
    block.row(2) << mu * ez + ex, 0, 0, 0;
    block.row(3) << mu * ez - ey, 0, 0, 0;          // |f_y| ≤ μ' f_z
    block.row(4) << mu * ez + ey, 0, 0, 0;
    block.row(5) << half_w * ez, -ex;               // |n_x| ≤ (w/2) f_z: COP across the sole
    block.row(6) << half_w * ez, ex;
    block.row(7) << half_l * ez, -ey;               // |n_y| ≤ (l/2) f_z: COP along the sole
    block.row(8) << half_l * ez, ey;
    // Yaw: the exact bounds for a rectangle whose corners each carry a force in the pyramid
    // (Caron, Pham, Nakamura, ICRA 2015), with X, Y the half-length and half-width:
    //   n_z ≤ μ'(X + Y) f_z − |Y f_x + μ' n_x| − |X f_y + μ' n_y|,
    //   n_z ≥ −μ'(X + Y) f_z + |Y f_x − μ' n_x| + |X f_y − μ' n_y|,
    // each absolute value split into its two signs. A foot loaded at an edge, or pushed sideways,
    // holds less yaw than a centred one.
    const double X = half_l, Y = half_w;
    int row = 9;
    for (const double s1 : {1.0, -1.0})
      for (const double s2 : {1.0, -1.0}) {
        const Eigen::RowVector3d f_part = mu * (X + Y) * ez - s1 * Y * ex - s2 * X * ey;
        block.row(row++) << f_part, -s1 * mu * ex - s2 * mu * ey - ez;  // upper bound on n_z
        block.row(row++) << f_part, s1 * mu * ex + s2 * mu * ey + ez;   // lower bound on n_z
      }
  }
}

void TrackingController::build(RobotData& data, const VecXCRef& q, const VecXCRef& v, const TrackingReference& ref,
                               TrackingProblem& p, TrackingWorkspace& ws, bool data_is_current) const {
  const RobotModel& model = *model_;
  const mjModel* m = model.mj();
  const mjData* d = data.mj();
  const int nv = model.nv(), nu = model.nu();
  RT_DEMAND(q.size() == model.nq() && v.size() == nv, "TrackingController::build: state size");
  RT_DEMAND(ref.q.size() == model.nq() && ref.v.size() == nv && ref.a.size() == nv,
            "TrackingController::build: reference size");
  if (!data_is_current) update_dynamics(model, data, q, v);

  p.nu = nu;
  p.contact = ref.contact;
  p.max_normal_force_n = ref.max_normal_force_n;
  p.desired_vertical_force_n = ref.desired_vertical_force_n;
  p.desired_cop_W = ref.desired_cop_W;
  p.M.resize(nv, nv);
  mj_fullM(m, p.M.data(), d->qM);  // symmetric: row- and column-major agree
  p.bias = Eigen::Map<const VecX>(d->qfrc_bias, nv);
  p.p_W_com = com_position(model, data);

  // Eq. (2): q̈̂ = q̈_ref + k_d (q̇_ref − q̇) + k_p (q_ref − q), the position error taken on the manifold.
  ws.q_err.resize(nv);
  mj_differentiatePos(m, ws.q_err.data(), 1.0, q.data(), ref.q.data());
  ws.qdd_hat = ref.a + kd_.cwiseProduct(ref.v - v) + kp_.cwiseProduct(ws.q_err);

  // Foot tasks for both feet (eq. 3–4) at the sole centres.
  p.J_feet.resize(12, nv);
  p.Jdot_v_feet.resize(12);
  ws.rdd_hat.resize(12);
  p.contact_feet.clear();
  p.r_contact_W.clear();
  p.R_contact_W.clear();
  ws.J_link.resize(3, 2 * nv);
  for (int foot = 0; foot < 2; ++foot) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const Iso3 X_W_link = link_pose(model, data, sole.link);
    const Vec3 p_W_sole = X_W_link * sole.p_L_center;
    // mj_jac writes 3 x nv row-major blocks: the transposes of column-major nv x 3 blocks.
    Eigen::Map<MatX> jp_t(ws.J_link.data(), nv, 3), jr_t(ws.J_link.data() + 3 * nv, nv, 3);
    mj_jac(m, d, jp_t.data(), jr_t.data(), p_W_sole.data(), model.links()[static_cast<std::size_t>(sole.link)].body);
    p.J_feet.middleRows(6 * foot, 3) = jp_t.transpose();
    p.J_feet.middleRows(6 * foot + 3, 3) = jr_t.transpose();
    p.Jdot_v_feet.segment<6>(6 * foot) = link_jdot_v(model, data, sole.link, sole.p_L_center);
    const Iso3& X_ref = ref.X_W_sole[static_cast<std::size_t>(foot)];
    // The reference is the sole frame; the link's own axes may point anywhere (DH-style frames).
    const Mat3 R_W_sole = X_W_link.linear() * sole.R_L_S;
    Vec6 err;
    err.head<3>() = X_ref.translation() - p_W_sole;
    err.tail<3>() = rotation_error(X_ref.linear(), R_W_sole);
    const Vec6 v_now = p.J_feet.middleRows<6>(6 * foot) * v;
    const Vec6 rdd = ref.a_sole[static_cast<std::size_t>(foot)] +
                     options_.foot_kd * (ref.v_sole[static_cast<std::size_t>(foot)] - v_now) + options_.foot_kp * err;
    p.rdd_desired[static_cast<std::size_t>(foot)] = rdd;
    ws.rdd_hat.segment<6>(6 * foot) = rdd;
    if (ref.contact[static_cast<std::size_t>(foot)]) {
      p.contact_feet.push_back(foot);
      p.r_contact_W.push_back(p_W_sole);
      // The floor is horizontal: limits act along W's vertical, with the sole rectangle turned by
      // the sole's heading (a tilted foot's own axes would tilt the friction cone).
      const Vec3 x_sole = R_W_sole.col(0);
      p.R_contact_W.push_back(AngleAxis(std::atan2(x_sole.y(), x_sole.x()), Vec3::UnitZ()).toRotationMatrix());
    }
  }
  // The foot Jacobians are zero outside the dofs of the legs' chains (feet_dofs_): products with
  // them run over those columns only.
  ws.J_K = p.J_feet(Eigen::all, feet_dofs_);

  // Eq. (5): q̈̂' = q̈̂ + J_c⁺ (r̈̂ − J_c q̈̂ − J̇_c q̇), J_c⁺ = J_cᵀ (J_c J_cᵀ + λI)⁻¹.
  ws.x_K = ws.qdd_hat(feet_dofs_);
  Eigen::Matrix<double, 12, 12> JJt;
  JJt.noalias() = ws.J_K * ws.J_K.transpose();
  JJt.diagonal().array() += options_.pinv_damping;
  Eigen::Matrix<double, 12, 1> e12 = ws.rdd_hat - p.Jdot_v_feet;
  e12.noalias() -= ws.J_K * ws.x_K;
  const Eigen::LLT<Eigen::Matrix<double, 12, 12>> llt12(JJt);
  e12 = llt12.solve(e12);
  ws.x_K.noalias() = ws.J_K.transpose() * e12;
  p.qdd_desired = ws.qdd_hat;
  p.qdd_desired(feet_dofs_) += ws.x_K;

  // Equation of motion: q̈ = M⁻¹ (S τ + J_fᵀ f − c) = G y + a0.
  const int nc = static_cast<int>(p.contact_feet.size());
  p.nf = 6 * nc;
  p.J_contact.resize(p.nf, nv);
  for (int i = 0; i < nc; ++i) p.J_contact.middleRows(6 * i, 6) = p.J_feet.middleRows(6 * p.contact_feet[static_cast<std::size_t>(i)], 6);
  const int ny = nu + p.nf;
  // G = M⁻¹ [S, J_fᵀ] through MuJoCo's sparse L'DL factor of M (mj_factorM ran in
  // update_dynamics), all right-hand sides at once.
  p.G.setZero(nv, ny);
  p.G.bottomLeftCorner(nu, nu).setIdentity();
  p.G.rightCols(p.nf) = p.J_contact.transpose();
  solve_mass_matrix(model, data, p.G);
  p.a0.resize(nv);
  mj_solveM(m, data.mj(), p.a0.data(), p.bias.data(), 1);
  p.a0 = -p.a0;

  // Eq. (9)–(11), (16), (17).
  p.P.setZero(2, p.nf);
  p.P_p.setZero(2 * nc, p.nf);
  p.V.setZero(3, p.nf);
  for (int i = 0; i < nc; ++i) {
    const Vec3& r = p.r_contact_W[static_cast<std::size_t>(i)];
    const Mat6 T = wrench_to_origin(r);
    p.P.middleCols(6 * i, 6) = moment_about(ref.desired_cop_W) * T;
    p.P_p.block(2 * i, 6 * i, 2, 6) = moment_about(r.head<2>()) * T;  // desired COP of a foot: its sole centre
    p.V.block(0, 6 * i, 3, 3) = skew(r - p.p_W_com);
    p.V.block(0, 6 * i + 3, 3, 3).setIdentity();
  }

  // Eq. (18). Z_q + Z_c = ½ |E y − e|² with E = [W_q^½ G; W_c^½ J_c G] and e the weighted
  // residuals at y = 0: one rank update gives both terms of A, one product both terms of b.
  const TrackingWeights& w = options_.weights;
  foot_weights(ref.contact, ws.w_c);
  ws.E.resize(nv + 12, ny);
  ws.e.resize(nv + 12);
  ws.E.topRows(nv).noalias() = w_q_.cwiseSqrt().asDiagonal() * p.G;
  ws.e.head(nv) = w_q_.cwiseSqrt().cwiseProduct(p.qdd_desired - p.a0);
  ws.G_K = p.G(feet_dofs_, Eigen::all);
  ws.x_K = p.a0(feet_dofs_);
  ws.E.bottomRows(12).noalias() = ws.J_K * ws.G_K;
  ws.E.bottomRows(12) = ws.w_c.cwiseSqrt().asDiagonal() * ws.E.bottomRows(12);
  e12 = ws.rdd_hat - p.Jdot_v_feet;
  e12.noalias() -= ws.J_K * ws.x_K;
  ws.e.tail(12) = ws.w_c.cwiseSqrt().cwiseProduct(e12);
  p.A.setZero(ny, ny);
  p.A.selfadjointView<Eigen::Lower>().rankUpdate(ws.E.transpose());
  p.b.noalias() = -ws.E.transpose() * ws.e;
  // Z_τ, Z_f with zero reference torque and force.
  p.A.topLeftCorner(nu, nu).diagonal().array() += w.torque;
  p.A.bottomRightCorner(p.nf, p.nf).diagonal().array() += w.force;
  // Z_b, Z_p, Z_m act on the forces only.
  p.A.triangularView<Eigen::StrictlyUpper>() = p.A.transpose();
  if (p.nf > 0) {
    auto A_ff = p.A.bottomRightCorner(p.nf, p.nf);
    A_ff.noalias() += w.cop * p.P.transpose() * p.P;
    A_ff.noalias() += w.foot_cop * p.P_p.transpose() * p.P_p;
    A_ff.noalias() += w.com_moment * p.V.transpose() * p.V;
    // Z_z = ½ W_z (Σ f_z − F_z)²: f_z is W's vertical component of each foot's force.
    if (w.vertical_force > 0) {
      for (int i = 0; i < nc; ++i)
        for (int j = 0; j < nc; ++j) A_ff(6 * i + 2, 6 * j + 2) += w.vertical_force;
      for (int i = 0; i < nc; ++i) p.b[nu + 6 * i + 2] -= w.vertical_force * ref.desired_vertical_force_n;
    }
  }
  contact_limits(p);
}

TrackingProblem TrackingController::build(RobotData& data, const VecXCRef& q, const VecXCRef& v,
                                          const TrackingReference& ref, bool data_is_current) const {
  TrackingProblem p;
  TrackingWorkspace ws;
  build(data, q, v, ref, p, ws, data_is_current);
  return p;
}

void TrackingController::solve(const TrackingProblem& p, TrackingCommand& c, TrackingWorkspace& ws) const {
  const int nu = p.nu, nf = p.nf;
  // A is positive definite (W_τ, W_f > 0 regularise every unknown), hence so are A_ττ and the
  // Schur complement of the wrenches.
  ws.llt_tau.compute(p.A.topLeftCorner(nu, nu));
  RT_DEMAND(ws.llt_tau.info() == Eigen::Success, "TrackingController: cost matrix is not positive definite");
  ws.z_tau = p.b.head(nu);
  ws.llt_tau.matrixL().solveInPlace(ws.z_tau);  // z = L⁻¹ b_τ
  c.closed_form_feasible = true;
  c.qp_iterations = 0;
  c.qp_status = QpStatus::Solved;
  c.f_contact.resize(nf);
  if (nf > 0) {
    ws.X = p.A.topRightCorner(nu, nf);
    ws.llt_tau.matrixL().solveInPlace(ws.X);  // X = L⁻¹ A_τf
    ws.A_red = p.A.bottomRightCorner(nf, nf);
    ws.A_red.noalias() -= ws.X.transpose() * ws.X;
    ws.b_red = p.b.tail(nf);
    ws.b_red.noalias() -= ws.X.transpose() * ws.z_tau;
    // The QP starts at the unconstrained minimum −A_red⁻¹ b_red (the paper's closed form) and only
    // iterates when that violates a contact limit.
    c.qp_status = ws.qp.solve(ws.A_red, ws.b_red, p.C_contact, p.d_contact, c.f_contact);
    RT_DEMAND(c.qp_status != QpStatus::NotConvex, "TrackingController: cost matrix is not positive definite");
    c.qp_iterations = ws.qp.iterations();
    c.closed_form_feasible = c.qp_iterations == 0;
    ws.z_tau.noalias() += ws.X * c.f_contact;
  }
  // τ = −A_ττ⁻¹ (b_τ + A_τf f) = −L⁻ᵀ (z + X f).
  c.tau_raw = -ws.z_tau;
  ws.llt_tau.matrixU().solveInPlace(c.tau_raw);
  c.qdd = p.a0;
  c.qdd.noalias() += p.G.leftCols(nu) * c.tau_raw;
  if (nf > 0) c.qdd.noalias() += p.G.rightCols(nf) * c.f_contact;
  const VecX& limit = model_->effort_limits();
  c.tau = c.tau_raw;
  c.saturated_joints = 0;
  for (int i = 0; i < nu; ++i) c.saturated_joints += limit[i] > 0 && std::abs(c.tau_raw[i]) > limit[i];
  c.torque_limited = false;
  if (options_.torque_limits && c.saturated_joints > 0 && solve_torque_limited(p, ws)) {
    c.torque_limited = true;
    c.tau = ws.y_full.head(nu);
    c.f_contact = ws.y_full.tail(nf);
    c.qdd = p.a0;
    c.qdd.noalias() += p.G * ws.y_full;
  }
  for (int i = 0; i < nu; ++i)
    if (limit[i] > 0 && std::abs(c.tau[i]) > limit[i]) c.tau[i] = std::copysign(limit[i], c.tau[i]);
}

bool TrackingController::solve_torque_limited(const TrackingProblem& p, TrackingWorkspace& ws) const {
  const int nu = p.nu, nf = p.nf, ny = nu + nf;
  const VecX& limit = model_->effort_limits();
  int limited = 0;
  for (int i = 0; i < nu; ++i) limited += limit[i] > 0;
  const auto nc = static_cast<int>(p.C_contact.rows());
  ws.C_full.setZero(nc + 2 * limited, ny);
  ws.d_full.resize(nc + 2 * limited);
  if (nc > 0) {
    ws.C_full.topRightCorner(nc, nf) = p.C_contact;
    ws.d_full.head(nc) = p.d_contact;
  }
  for (int i = 0, row = nc; i < nu; ++i) {
    if (!(limit[i] > 0)) continue;
    ws.C_full(row, i) = 1;  // τ_i ≥ −limit
    ws.d_full[row++] = -limit[i];
    ws.C_full(row, i) = -1;  // −τ_i ≥ −limit
    ws.d_full[row++] = -limit[i];
  }
  // τ = 0 with the wrenches inside their cones is feasible, so only an iteration limit or a
  // numerical failure ends here without a solution; the caller then clips the unconstrained one.
  return ws.qp_full.solve(p.A, p.b, ws.C_full, ws.d_full, ws.y_full) == QpStatus::Solved;
}

TrackingCommand TrackingController::solve(const TrackingProblem& p) const {
  TrackingCommand c;
  TrackingWorkspace ws;
  solve(p, c, ws);
  return c;
}

std::array<double, 8> TrackingController::cost_terms(const TrackingProblem& p, const VecX& y) const {
  const TrackingWeights& w = options_.weights;
  const VecX tau = y.head(p.nu), f = y.tail(p.nf);
  // q̈ from the equation of motion itself: M q̈ = S τ + J_fᵀ f − c.
  VecX generalized = -p.bias;
  generalized.tail(p.nu) += tau;
  generalized += p.J_contact.transpose() * f;
  const VecX qdd = p.M.ldlt().solve(generalized);

  // Total force and moment about the world origin, then about the desired COP.
  Vec3 F = Vec3::Zero(), N = Vec3::Zero(), N_com = Vec3::Zero();
  double Z_p = 0;
  for (std::size_t i = 0; i < p.contact_feet.size(); ++i) {
    const Vec3 fi = f.segment<3>(static_cast<Eigen::Index>(6 * i));
    const Vec3 ni = f.segment<3>(static_cast<Eigen::Index>(6 * i + 3));
    const Vec3& r = p.r_contact_W[i];
    F += fi;
    N += r.cross(fi) + ni;
    N_com += (r - p.p_W_com).cross(fi) + ni;
    // Moment of this foot's wrench about its own sole centre (r itself): just n_i.
    Z_p += 0.5 * w.foot_cop * ni.head<2>().squaredNorm();
  }
  const Vec3 r_b(p.desired_cop_W.x(), p.desired_cop_W.y(), 0);
  const Vec3 N_b = N - r_b.cross(F);
  const double Z_b = 0.5 * w.cop * N_b.head<2>().squaredNorm();
  const double Z_q = 0.5 * (p.qdd_desired - qdd).cwiseAbs2().dot(w_q_);
  double Z_c = 0;
  VecX w_c;
  foot_weights(p.contact, w_c);
  for (int foot = 0; foot < 2; ++foot) {
    const Vec6 rdd = p.J_feet.middleRows(6 * foot, 6) * qdd + p.Jdot_v_feet.segment<6>(6 * foot);
    const Vec6 e = p.rdd_desired[static_cast<std::size_t>(foot)] - rdd;
    Z_c += 0.5 * e.dot(w_c.segment<6>(6 * foot).cwiseProduct(e));
  }
  const double Z_tau = 0.5 * w.torque * tau.squaredNorm();
  const double Z_f = 0.5 * w.force * f.squaredNorm();
  const double Z_m = 0.5 * w.com_moment * N_com.squaredNorm();
  const double Z_z = p.nf > 0 ? 0.5 * w.vertical_force * std::pow(F.z() - p.desired_vertical_force_n, 2) : 0.0;
  return {Z_b, Z_q, Z_c, Z_tau, Z_f, Z_p, Z_m, Z_z};
}

}  // namespace rt
