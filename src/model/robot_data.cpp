#include "retarget/model/robot_data.hpp"

#include <mujoco/mujoco.h>

#include <utility>

#include "retarget/core/error.hpp"

namespace rt {

RobotData::RobotData(const RobotModel& model) : model_(&model), mj_(mj_makeData(model.mj())) {
  RT_DEMAND(mj_ != nullptr, "mj_makeData failed");
  // Start at the standing pose, at rest, with every derived quantity consistent.
  mju_copy(mj_->qpos, model.standing_q().data(), model.nq());
  mj_forward(model.mj(), mj_);
}

RobotData::~RobotData() {
  if (mj_) mj_deleteData(mj_);
}

RobotData::RobotData(RobotData&& other) noexcept : model_(other.model_), mj_(std::exchange(other.mj_, nullptr)) {}

RobotData& RobotData::operator=(RobotData&& other) noexcept {
  if (this != &other) {
    if (mj_) mj_deleteData(mj_);
    model_ = other.model_;
    mj_ = std::exchange(other.mj_, nullptr);
  }
  return *this;
}

}  // namespace rt
