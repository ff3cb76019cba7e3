#pragma once
/// RobotData: the per-evaluation workspace of a RobotModel (owns one mjData). One per thread.
/// A new RobotData holds the model's standing pose at rest (qpos = standing_q(), qvel = 0,
/// mj_forward done). The model must outlive it.

#include <memory>

#include "retarget/model/robot_model.hpp"

struct mjData_;
typedef struct mjData_ mjData;

namespace rt {

class RobotData {
 public:
  explicit RobotData(const RobotModel& model);
  ~RobotData();
  RobotData(const RobotData&) = delete;
  RobotData& operator=(const RobotData&) = delete;
  RobotData(RobotData&&) noexcept;
  RobotData& operator=(RobotData&&) noexcept;

  const RobotModel& model() const { return *model_; }
  mjData* mj() { return mj_; }
  const mjData* mj() const { return mj_; }

 private:
  const RobotModel* model_;
  mjData* mj_;
};

}  // namespace rt
