#pragma once
/// Bridges a Reference (joint columns by name, any order) and a RobotModel (generalised coordinates
/// in model order): mapping and per-frame configurations (the NPZ body arrays: npz_layout.hpp).

#include <vector>

#include "retarget/model/robot_data.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

class ReferenceRobotMap {
 public:
  /// Maps every movable joint of the model to a reference column. InputError naming the first
  /// missing or unknown joint when the reference's joint set differs from the robot's.
  ReferenceRobotMap(const RobotModel& model, const Reference& reference, const std::string& where);

  /// Generalised configuration q (nq) of frame `frame`.
  VecX q(const Reference& reference, int frame) const;
  /// All frames as an nq x T matrix.
  MatX q_all(const Reference& reference) const;
  /// The reference row (joint_pos) of movable joint i (model order).
  int column_of_movable(int i) const { return column_of_movable_[static_cast<std::size_t>(i)]; }

 private:
  const RobotModel* model_;
  std::vector<int> column_of_movable_;  ///< movable joint i (model order) -> reference row
};

/// A reference that holds configuration `q` (nq) for `duration_s` at `fps`, both feet in contact
/// (standing tests, benchmarks).
Reference constant_reference(const RobotModel& model, const VecX& q, double duration_s, double fps);

/// The reference played `time_scale` times slower (> 1) or faster (< 1) at the same frame rate:
/// positions and joints interpolated linearly, root orientation by slerp, contacts from the nearest
/// frame, COM/COP linearly. Provenance (extra_meta_json) is kept.
Reference retime_reference(const Reference& reference, double time_scale);

}  // namespace rt
