#include "retarget/control/tracking_controller.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Cholesky>

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
}

VecX TrackingController::foot_weights(const std::array<bool, 2>& contact) const {
  const TrackingWeights& w = options_.weights;
  VecX w_c(12);
  for (int foot = 0; foot < 2; ++foot) {
    const bool stance = contact[static_cast<std::size_t>(foot)];
    w_c.segment<3>(6 * foot).setConstant(stance ? w.stance_foot : w.foot_linear);
    w_c.segment<3>(6 * foot + 3).setConstant(stance ? w.stance_foot : w.foot_angular);
  }
  return w_c;
}

TrackingProblem TrackingController::build(RobotData& data, const VecXCRef& q, const VecXCRef& v,
                                          const TrackingReference& ref, bool data_is_current) const {
  const RobotModel& model = *model_;
  const int nv = model.nv(), nu = model.nu();
  RT_DEMAND(q.size() == model.nq() && v.size() == nv, "TrackingController::build: state size");
  RT_DEMAND(ref.q.size() == model.nq() && ref.v.size() == nv && ref.a.size() == nv,
            "TrackingController::build: reference size");
  if (!data_is_current) update_dynamics(model, data, q, v);

  TrackingProblem p;
  p.nu = nu;
  p.contact = ref.contact;
  p.desired_cop_W = ref.desired_cop_W;
  p.M = mass_matrix(model, data);
  p.bias = bias_forces(model, data);
  p.p_W_com = com_position(model, data);

  // Eq. (2): q̈̂ = q̈_ref + k_d (q̇_ref − q̇) + k_p (q_ref − q), the position error taken on the manifold.
  const VecX q_err = difference(model, q, ref.q, 1.0);
  VecX qdd_hat = ref.a + kd_.cwiseProduct(ref.v - v) + kp_.cwiseProduct(q_err);

  // Foot tasks for both feet (eq. 3–4) at the sole centres.
  p.J_feet.resize(12, nv);
  p.Jdot_v_feet.resize(12);
  VecX rdd_hat(12);
  const std::vector<Vec6> jdot_v = links_jdot_v(model, data, {model.soles()[0].link, model.soles()[1].link},
                                                 {model.soles()[0].p_L_center, model.soles()[1].p_L_center});
  for (int foot = 0; foot < 2; ++foot) {
    const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
    const MatX J = link_jacobian(model, data, sole.link, sole.p_L_center);
    p.J_feet.middleRows(6 * foot, 6) = J;
    p.Jdot_v_feet.segment<6>(6 * foot) = jdot_v[static_cast<std::size_t>(foot)];
    const Iso3 X_W_link = link_pose(model, data, sole.link);
    const Vec3 p_W_sole = X_W_link * sole.p_L_center;
    const Iso3& X_ref = ref.X_W_sole[static_cast<std::size_t>(foot)];
    Vec6 err;
    err.head<3>() = X_ref.translation() - p_W_sole;
    err.tail<3>() = rotation_error(X_ref.linear(), X_W_link.linear());
    const Vec6 v_now = J * v;
    const Vec6 rdd = ref.a_sole[static_cast<std::size_t>(foot)] +
                     options_.foot_kd * (ref.v_sole[static_cast<std::size_t>(foot)] - v_now) + options_.foot_kp * err;
    p.rdd_desired[static_cast<std::size_t>(foot)] = rdd;
    rdd_hat.segment<6>(6 * foot) = rdd;
    if (ref.contact[static_cast<std::size_t>(foot)]) {
      p.contact_feet.push_back(foot);
      p.r_contact_W.push_back(p_W_sole);
    }
  }

  // Eq. (5): q̈̂' = q̈̂ + J_c⁺ (r̈̂ − J_c q̈̂ − J̇_c q̇), J_c⁺ = J_cᵀ (J_c J_cᵀ + λI)⁻¹.
  const MatX JJt = p.J_feet * p.J_feet.transpose() + options_.pinv_damping * MatX::Identity(12, 12);
  p.qdd_desired = qdd_hat + p.J_feet.transpose() * JJt.ldlt().solve(rdd_hat - p.J_feet * qdd_hat - p.Jdot_v_feet);

  // Equation of motion: q̈ = M⁻¹ (S τ + J_fᵀ f − c) = G y + a0.
  const int nc = static_cast<int>(p.contact_feet.size());
  p.nf = 6 * nc;
  p.J_contact.resize(p.nf, nv);
  for (int i = 0; i < nc; ++i) p.J_contact.middleRows(6 * i, 6) = p.J_feet.middleRows(6 * p.contact_feet[static_cast<std::size_t>(i)], 6);
  const int ny = nu + p.nf;
  // G = M⁻¹ [S, J_fᵀ] through MuJoCo's sparse L'DL factor of M (mj_factorM ran in
  // update_dynamics): each column of a column-major matrix is one right-hand side.
  MatX SJ = MatX::Zero(nv, ny);
  SJ.bottomLeftCorner(nu, nu).setIdentity();
  SJ.rightCols(p.nf) = p.J_contact.transpose();
  p.G.resize(nv, ny);
  mj_solveM(model.mj(), data.mj(), p.G.data(), SJ.data(), ny);
  p.a0.resize(nv);
  mj_solveM(model.mj(), data.mj(), p.a0.data(), p.bias.data(), 1);
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

  // Eq. (18): accumulate A and b term by term.
  const TrackingWeights& w = options_.weights;
  p.A.setZero(ny, ny);
  p.b.setZero(ny);
  // Z_q = ½ |q̈̂' − q̈|²_Wq   (rank updates fill the lower triangle; mirrored below)
  const MatX Gs = w_q_.cwiseSqrt().asDiagonal() * p.G;
  p.A.selfadjointView<Eigen::Lower>().rankUpdate(Gs.transpose());
  p.b.noalias() -= p.G.transpose() * w_q_.cwiseProduct(p.qdd_desired - p.a0);
  // Z_c = ½ |r̈̂ − J_c q̈ − J̇_c q̇|²_Wc
  const VecX w_c = foot_weights(ref.contact);
  const MatX H = p.J_feet * p.G;
  const VecX d = rdd_hat - p.J_feet * p.a0 - p.Jdot_v_feet;
  p.A.selfadjointView<Eigen::Lower>().rankUpdate((w_c.cwiseSqrt().asDiagonal() * H).transpose());
  p.b.noalias() -= H.transpose() * w_c.cwiseProduct(d);
  // Z_τ, Z_f with zero reference torque and force.
  p.A.topLeftCorner(nu, nu).diagonal().array() += w.torque;
  p.A.bottomRightCorner(p.nf, p.nf).diagonal().array() += w.force;
  // Z_b, Z_p, Z_m act on the forces only.
  p.A.triangularView<Eigen::StrictlyUpper>() = p.A.transpose();
  if (p.nf > 0) {
    p.A.bottomRightCorner(p.nf, p.nf) += w.cop * p.P.transpose() * p.P + w.foot_cop * p.P_p.transpose() * p.P_p +
                                          w.com_moment * p.V.transpose() * p.V;
  }
  return p;
}

TrackingCommand TrackingController::solve(const TrackingProblem& p) const {
  // A is positive definite (W_τ, W_f > 0 regularise every unknown): Cholesky.
  const Eigen::LLT<MatX> llt(p.A);
  RT_DEMAND(llt.info() == Eigen::Success, "TrackingController: cost matrix is not positive definite");
  const VecX y = -llt.solve(p.b);
  TrackingCommand c;
  c.tau_raw = y.head(p.nu);
  c.f_contact = y.tail(p.nf);
  c.qdd = p.G * y + p.a0;
  const VecX& limit = model_->effort_limits();
  c.tau = c.tau_raw;
  for (int i = 0; i < p.nu; ++i) {
    if (limit[i] > 0 && std::abs(c.tau[i]) > limit[i]) {
      c.tau[i] = std::copysign(limit[i], c.tau[i]);
      ++c.saturated_joints;
    }
  }
  return c;
}

std::array<double, 7> TrackingController::cost_terms(const TrackingProblem& p, const VecX& y) const {
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
  const VecX w_c = foot_weights(p.contact);
  for (int foot = 0; foot < 2; ++foot) {
    const Vec6 rdd = p.J_feet.middleRows(6 * foot, 6) * qdd + p.Jdot_v_feet.segment<6>(6 * foot);
    const Vec6 e = p.rdd_desired[static_cast<std::size_t>(foot)] - rdd;
    Z_c += 0.5 * e.dot(w_c.segment<6>(6 * foot).cwiseProduct(e));
  }
  const double Z_tau = 0.5 * w.torque * tau.squaredNorm();
  const double Z_f = 0.5 * w.force * f.squaredNorm();
  const double Z_m = 0.5 * w.com_moment * N_com.squaredNorm();
  return {Z_b, Z_q, Z_c, Z_tau, Z_f, Z_p, Z_m};
}

}  // namespace rt
