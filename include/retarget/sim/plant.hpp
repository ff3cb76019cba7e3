#pragma once
/// Plant: the simulated robot of the dynamics check (design.md §3.5) — the RobotModel's generated
/// MuJoCo model with its own mjData, driven by joint torques through the torque motors, and the
/// contact quantities the check measures (per-foot normal force and COP, non-sole floor contacts).

#include <array>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/model/robot_model.hpp"

struct mjData_;
typedef struct mjData_ mjData;

namespace rt {

struct FootContact {
  double normal_force_n = 0;  ///< [N] total normal force between the sole and the floor
  Vec2 cop_W = Vec2::Zero();  ///< [m] this foot's centre of pressure (valid when the force > 0)
  Vec3 force_W = Vec3::Zero();  ///< [N] total contact force on the foot (floor on robot)
};

struct ContactState {
  std::array<FootContact, 2> feet;
  double normal_force_n = 0;          ///< [N] sum over all floor contacts
  Vec2 cop_W = Vec2::Zero();          ///< [m] overall COP (valid when normal_force_n > 0)
  std::vector<int> non_sole_links;    ///< links (other than the soles) touching the floor
};

/// Differences of the simulated robot from its model (robustness runs of the check): the
/// controllers keep the nominal model.
struct PlantOptions {
  double mass_scale = 1.0;     ///< every body's mass and inertia scaled by this
  double floor_friction = 0;   ///< > 0: sliding friction of every contact (else the robot.yaml value)
};

class Plant {
 public:
  explicit Plant(const RobotModel& model, const PlantOptions& options = {});
  ~Plant();
  Plant(const Plant&) = delete;
  Plant& operator=(const Plant&) = delete;

  /// Sets the state (q: nq, v: nv), zero controls, and computes contacts for it.
  void reset(const VecX& q, const VecX& v);
  /// Runs MuJoCo's position and velocity stages of the next step for the current state
  /// (mj_step1): afterwards mj() holds its kinematics, mass matrix and bias forces (for
  /// assign_dynamics), while the contact list is that of the next step and contacts() must not be
  /// read until step() completes it.
  void begin_step();
  /// Applies `tau` (nu, model order; clamped by the motors' force ranges) for `steps` simulation
  /// steps of the model's timestep, completing a begun step first.
  void step(const VecX& tau, int steps);

  VecX q() const;
  VecX v() const;
  double time_s() const;
  /// Contact quantities of the current state (from MuJoCo's contact list).
  ContactState contacts() const;
  /// MuJoCo flagged a numerical instability (it then resets the state): the run is invalid.
  bool unstable() const { return unstable_; }

  const RobotModel& model() const { return *model_; }
  const mjData* mj() const { return d_; }
  /// Whether the simulated model is the robot's own (no mass scale or friction change): then the
  /// plant's mjData may stand in for the controller's dynamics of the same state.
  bool nominal() const { return owned_ == nullptr; }

 private:
  const RobotModel* model_;
  const mjModel* m_ = nullptr;   ///< the simulated model: the robot's, or owned_
  mjModel* owned_ = nullptr;
  mjData* d_ = nullptr;
  bool unstable_ = false;
  bool step_begun_ = false;
};

}  // namespace rt
