#include "retarget/sim/reference_signal.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/balance/com_motion.hpp"
#include "retarget/core/error.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

namespace {

Vec3 rotation_vector(const Mat3& R) {
  const AngleAxis aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

ReferenceSignal::ReferenceSignal(const RobotModel& model, RobotData& data, const Reference& ref, double com_smoothing_s)
    : model_(&model) {
  const int T = ref.num_frames();
  if (T < 1) throw InputError("reference", "no frames");
  if (!ref.has_contacts()) throw InternalError("ReferenceSignal: the reference needs a contact schedule");
  fps_ = ref.fps;
  duration_s_ = (T - 1) / fps_;
  const ReferenceRobotMap map(model, ref, "reference");
  q_ = map.q_all(ref);
  const int nv = model.nv();
  const double dt = 1.0 / fps_;
  v_.setZero(nv, T);
  a_.setZero(nv, T);
  for (int k = 0; k < T; ++k) {
    const int a = std::max(0, k - 1), b = std::min(T - 1, k + 1);
    if (b > a) v_.col(k) = difference(model, q_.col(a), q_.col(b), (b - a) * dt);
  }
  for (int k = 0; k < T; ++k) {
    const int a = std::max(0, k - 1), b = std::min(T - 1, k + 1);
    if (b > a) a_.col(k) = (v_.col(b) - v_.col(a)) / ((b - a) * dt);
  }
  const auto R_L_sole = sole_frames_in_links(model, data);
  com_.resize(3, T);
  for (int foot = 0; foot < 2; ++foot) {
    sole_[static_cast<std::size_t>(foot)].resize(static_cast<std::size_t>(T));
    sole_v_[static_cast<std::size_t>(foot)].setZero(6, T);
    sole_a_[static_cast<std::size_t>(foot)].setZero(6, T);
    contact_[static_cast<std::size_t>(foot)] = ref.contact[static_cast<std::size_t>(foot)];
  }
  for (int k = 0; k < T; ++k) {
    update_kinematics(model, data, q_.col(k));
    com_.col(k) = com_position(model, data);
    for (int foot = 0; foot < 2; ++foot) {
      const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
      const Iso3 X_link = link_pose(model, data, sole.link);
      Iso3 X = Iso3::Identity();
      X.linear() = X_link.linear() * R_L_sole[static_cast<std::size_t>(foot)];
      X.translation() = X_link * sole.p_L_center;
      sole_[static_cast<std::size_t>(foot)][static_cast<std::size_t>(k)] = X;
    }
  }
  com_derivatives_ = com_derivatives(com_.topRows(2), fps_, com_smoothing_s);
  // Foot velocities and accelerations by central differences of the poses.
  for (int foot = 0; foot < 2; ++foot) {
    const auto& X = sole_[static_cast<std::size_t>(foot)];
    auto& V = sole_v_[static_cast<std::size_t>(foot)];
    auto& A = sole_a_[static_cast<std::size_t>(foot)];
    for (int k = 0; k < T; ++k) {
      const int a = std::max(0, k - 1), b = std::min(T - 1, k + 1);
      if (b == a) continue;
      const double h = (b - a) * dt;
      V.col(k).head<3>() = (X[static_cast<std::size_t>(b)].translation() - X[static_cast<std::size_t>(a)].translation()) / h;
      V.col(k).tail<3>() = rotation_vector(X[static_cast<std::size_t>(b)].linear() * X[static_cast<std::size_t>(a)].linear().transpose()) / h;
    }
    for (int k = 0; k < T; ++k) {
      const int a = std::max(0, k - 1), b = std::min(T - 1, k + 1);
      if (b > a) A.col(k) = (V.col(b) - V.col(a)) / ((b - a) * dt);
    }
  }
}

Eigen::Matrix<double, 5, 2> ReferenceSignal::com_motion_at(double t_s, const TrunkTransform& map) const {
  const int T = num_frames();
  const bool inside = t_s >= 0 && t_s <= duration_s_;
  const double s = std::clamp(t_s, 0.0, duration_s_) * fps_;
  const int k = std::min(static_cast<int>(std::floor(s)), T - 1);
  const int k1 = std::min(k + 1, T - 1);
  const double w = s - k;
  Eigen::Matrix<double, 5, 2> out = Eigen::Matrix<double, 5, 2>::Zero();
  out.row(0) = map.apply_position((1 - w) * com_.col(k) + w * com_.col(k1)).head<2>().transpose();
  if (!inside) return out;
  const Mat2 L = map.linear().topLeftCorner<2, 2>();
  for (std::size_t order = 0; order < com_derivatives_.size(); ++order) {
    const Eigen::Matrix2Xd& d = com_derivatives_[order];
    out.row(static_cast<Eigen::Index>(order) + 1) = (L * ((1 - w) * d.col(k) + w * d.col(k1))).transpose();
  }
  return out;
}

std::array<bool, 2> ReferenceSignal::contact_at(double t_s) const {
  const int k = std::clamp(static_cast<int>(std::lround(t_s * fps_)), 0, num_frames() - 1);
  return {contact_[0][static_cast<std::size_t>(k)] != 0, contact_[1][static_cast<std::size_t>(k)] != 0};
}

Vec3 ReferenceSignal::com_at(double t_s, const TrunkTransform& map) const {
  const int T = num_frames();
  const double s = std::clamp(t_s, 0.0, duration_s_) * fps_;
  const int k = std::min(static_cast<int>(std::floor(s)), T - 1);
  const int k1 = std::min(k + 1, T - 1);
  const double w = s - k;
  return map.apply_position((1 - w) * com_.col(k) + w * com_.col(k1));
}

ReferenceSample ReferenceSignal::at(double t_s, const TrunkTransform& map) const {
  const RobotModel& model = *model_;
  const int T = num_frames();
  const double s = std::clamp(t_s, 0.0, duration_s_) * fps_;
  const int k = std::min(static_cast<int>(std::floor(s)), T - 1);
  const int k1 = std::min(k + 1, T - 1);
  const double w = s - k;
  ReferenceSample r;
  r.q = integrate(model, q_.col(k), difference(model, q_.col(k), q_.col(k1), 1.0) * w, 1.0);
  r.v = (1 - w) * v_.col(k) + w * v_.col(k1);
  r.a = (1 - w) * a_.col(k) + w * a_.col(k1);
  r.p_W_com = map.apply_position((1 - w) * com_.col(k) + w * com_.col(k1));
  r.contact = contact_at(t_s);
  // Map the root: position by eq. (22), orientation by eq. (23), velocities rotated by Ω.
  const Mat3 Omega = map.Omega();
  const Mat3 L = map.linear();  // positions map affinely: their derivatives by the linear part
  r.q.head<3>() = map.apply_position(r.q.head<3>());
  const Quat q_root = map.apply_orientation(Quat(r.q[3], r.q[4], r.q[5], r.q[6]));
  r.q.segment<4>(3) << q_root.w(), q_root.x(), q_root.y(), q_root.z();
  r.v.head<3>() = L * r.v.head<3>();
  r.a.head<3>() = L * r.a.head<3>();  // angular parts are in the root frame: unchanged
  for (int foot = 0; foot < 2; ++foot) {
    const auto f = static_cast<std::size_t>(foot);
    const Iso3& Xa = sole_[f][static_cast<std::size_t>(k)];
    const Iso3& Xb = sole_[f][static_cast<std::size_t>(k1)];
    Iso3 X = Iso3::Identity();
    X.translation() = map.apply_position((1 - w) * Xa.translation() + w * Xb.translation());
    X.linear() = Omega * Quat(Xa.linear()).slerp(w, Quat(Xb.linear())).toRotationMatrix();
    r.X_W_sole[f] = X;
    Vec6 v = (1 - w) * sole_v_[f].col(k) + w * sole_v_[f].col(k1);
    Vec6 a = (1 - w) * sole_a_[f].col(k) + w * sole_a_[f].col(k1);
    v.head<3>() = L * v.head<3>().eval();
    v.tail<3>() = Omega * v.tail<3>().eval();
    a.head<3>() = L * a.head<3>().eval();
    a.tail<3>() = Omega * a.tail<3>().eval();
    r.v_sole[f] = v;
    r.a_sole[f] = a;
  }
  return r;
}

}  // namespace rt
