#include "retarget/reference/robot_mapping.hpp"

#include <cmath>
#include <map>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt {

ReferenceRobotMap::ReferenceRobotMap(const RobotModel& model, const Reference& ref, const std::string& where)
    : model_(&model) {
  std::map<std::string, int> row;
  for (std::size_t i = 0; i < ref.joint_names.size(); ++i) row[ref.joint_names[i]] = static_cast<int>(i);
  if (static_cast<int>(ref.joint_names.size()) != model.nu())
    throw InputError(where, "the reference has " + std::to_string(ref.joint_names.size()) + " joints, robot '" +
                                model.name() + "' has " + std::to_string(model.nu()));
  column_of_movable_.resize(static_cast<std::size_t>(model.nu()));
  for (int i = 0; i < model.nu(); ++i) {
    const std::string& name = model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(i)])].name;
    const auto it = row.find(name);
    if (it == row.end())
      throw InputError(where, "robot '" + model.name() + "' joint '" + name + "' is not in the reference");
    column_of_movable_[static_cast<std::size_t>(i)] = it->second;
  }
}

VecX ReferenceRobotMap::q(const Reference& ref, int frame) const {
  VecX q(model_->nq());
  q.head<3>() = ref.root_pos_W.col(frame);
  const Quat r = model_->root_body_orientation(ref.root_quat_W[static_cast<std::size_t>(frame)]);
  q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
  for (int i = 0; i < model_->nu(); ++i) q[7 + i] = ref.joint_pos(column_of_movable_[static_cast<std::size_t>(i)], frame);
  return q;
}

MatX ReferenceRobotMap::q_all(const Reference& ref) const {
  MatX out(model_->nq(), ref.num_frames());
  for (int f = 0; f < ref.num_frames(); ++f) out.col(f) = q(ref, f);
  return out;
}

Reference constant_reference(const RobotModel& model, const VecX& q, double duration_s, double fps) {
  RT_DEMAND(q.size() == model.nq() && fps > 0 && duration_s >= 0, "constant_reference: bad arguments");
  const int T = static_cast<int>(std::floor(duration_s * fps + 1e-9)) + 1;
  Reference ref;
  ref.robot_name = model.name();
  ref.fps = fps;
  for (int k : model.export_joint_order())
    ref.joint_names.push_back(model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(k)])].name);
  ref.root_pos_W = q.head<3>().replicate(1, T);
  ref.root_quat_W.assign(static_cast<std::size_t>(T), model.root_link_orientation(Quat(q[3], q[4], q[5], q[6]).normalized()));
  ref.joint_pos.resize(static_cast<Eigen::Index>(ref.joint_names.size()), T);
  for (std::size_t c = 0; c < ref.joint_names.size(); ++c)
    ref.joint_pos.row(static_cast<Eigen::Index>(c)).setConstant(q[7 + model.export_joint_order()[c]]);
  for (auto& c : ref.contact) c.assign(static_cast<std::size_t>(T), 1);
  return ref;
}

Reference retime_reference(const Reference& in, double S) {
  if (!(S >= 0.05 && S <= 20)) throw InputError("--time-scale", "must be in [0.05, 20], got " + std::to_string(S));
  const int T = in.num_frames();
  if (S == 1.0 || T < 2) return in;
  const int T_out = static_cast<int>(std::floor((T - 1) * S + 1e-9)) + 1;
  Reference out = in;
  out.root_pos_W.resize(3, T_out);
  out.root_quat_W.resize(static_cast<std::size_t>(T_out));
  out.joint_pos.resize(in.joint_pos.rows(), T_out);
  for (auto& c : out.contact)
    if (!c.empty()) c.resize(static_cast<std::size_t>(T_out));
  if (in.com_W.cols() == T) out.com_W.resize(3, T_out);
  if (in.cop_W.cols() == T) out.cop_W.resize(2, T_out);
  for (int k = 0; k < T_out; ++k) {
    const double s = std::min(k / S, static_cast<double>(T - 1));
    const int i = std::min(static_cast<int>(s), T - 1), j = std::min(i + 1, T - 1);
    const double w = s - i;
    out.root_pos_W.col(k) = (1 - w) * in.root_pos_W.col(i) + w * in.root_pos_W.col(j);
    out.root_quat_W[static_cast<std::size_t>(k)] =
        in.root_quat_W[static_cast<std::size_t>(i)].slerp(w, in.root_quat_W[static_cast<std::size_t>(j)]).normalized();
    out.joint_pos.col(k) = (1 - w) * in.joint_pos.col(i) + w * in.joint_pos.col(j);
    const std::size_t nearest = static_cast<std::size_t>(w < 0.5 ? i : j);
    for (int foot = 0; foot < 2; ++foot)
      if (!in.contact[static_cast<std::size_t>(foot)].empty())
        out.contact[static_cast<std::size_t>(foot)][static_cast<std::size_t>(k)] = in.contact[static_cast<std::size_t>(foot)][nearest];
    if (out.com_W.cols() == T_out) out.com_W.col(k) = (1 - w) * in.com_W.col(i) + w * in.com_W.col(j);
    if (out.cop_W.cols() == T_out) out.cop_W.col(k) = (1 - w) * in.cop_W.col(i) + w * in.cop_W.col(j);
  }
  return out;
}

}  // namespace rt
