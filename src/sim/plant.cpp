#include "retarget/sim/plant.hpp"

#include <mujoco/mujoco.h>

#include "retarget/core/error.hpp"

namespace rt {

Plant::Plant(const RobotModel& model, const PlantOptions& options) : model_(&model) {
  if (!(options.mass_scale > 0 && options.mass_scale <= 10 && options.floor_friction >= 0 && options.floor_friction <= 10))
    throw InputError("check", "mass scale must be in (0, 10] and floor friction in [0, 10]");
  m_ = model.mj();
  if (options.mass_scale != 1 || options.floor_friction > 0) {
    // The plant's own copy: the controllers keep the nominal model, as on a real robot whose
    // masses or floor differ from its description.
    owned_ = mj_copyModel(nullptr, model.mj());
    if (!owned_) throw InternalError("Plant: mj_copyModel failed");
    for (int b = 0; b < owned_->nbody; ++b) {
      owned_->body_mass[b] *= options.mass_scale;
      for (int k = 0; k < 3; ++k) owned_->body_inertia[3 * b + k] *= options.mass_scale;
    }
    // The generated model collides by explicit floor pairs only (collision="predefined"), whose
    // parameters do not come from their geoms: the pairs' two tangential coefficients are what
    // the contacts use. The geoms get it too, so that the copy reads the same either way.
    if (options.floor_friction > 0) {
      for (int p = 0; p < owned_->npair; ++p)
        for (int k = 0; k < 2; ++k) owned_->pair_friction[5 * p + k] = options.floor_friction;
      for (int g = 0; g < owned_->ngeom; ++g) owned_->geom_friction[3 * g] = options.floor_friction;
    }
    // Derived constants (subtree masses, ...) of the changed model.
    mjData* scratch = mj_makeData(owned_);
    if (!scratch) throw InternalError("Plant: mj_makeData failed");
    mj_setConst(owned_, scratch);
    mj_deleteData(scratch);
    m_ = owned_;
  }
  d_ = mj_makeData(m_);
  if (!d_) throw InternalError("Plant: mj_makeData failed");
}

Plant::~Plant() {
  mj_deleteData(d_);
  if (owned_) mj_deleteModel(owned_);
}

void Plant::reset(const VecX& q, const VecX& v) {
  const mjModel* m = m_;
  RT_DEMAND(q.size() == m->nq && v.size() == m->nv, "Plant::reset: state size");
  mj_resetData(m, d_);
  mju_copy(d_->qpos, q.data(), m->nq);
  mju_copy(d_->qvel, v.data(), m->nv);
  mju_zero(d_->ctrl, m->nu);
  mj_forward(m, d_);
  unstable_ = false;
  step_begun_ = false;
}

void Plant::begin_step() {
  RT_DEMAND(!step_begun_, "Plant::begin_step: the step has begun already");
  mj_step1(m_, d_);
  step_begun_ = true;
}

void Plant::step(const VecX& tau, int steps) {
  const mjModel* m = m_;
  RT_DEMAND(tau.size() == m->nu && steps >= 1, "Plant::step: torque size or step count");
  mju_copy(d_->ctrl, tau.data(), m->nu);
  for (int i = 0; i < steps; ++i) {
    // For the Euler integrator mj_step1 + mj_step2 is mj_step.
    if (step_begun_)
      mj_step2(m, d_);
    else
      mj_step(m, d_);
    step_begun_ = false;
    if (d_->warning[mjWARN_BADQACC].number > 0) unstable_ = true;
  }
}

VecX Plant::q() const { return Eigen::Map<const VecX>(d_->qpos, m_->nq); }
VecX Plant::v() const { return Eigen::Map<const VecX>(d_->qvel, m_->nv); }
double Plant::time_s() const { return d_->time; }

ContactState Plant::contacts() const {
  RT_DEMAND(!step_begun_, "Plant::contacts: read during a begun step");
  const mjModel* m = m_;
  ContactState s;
  Vec3 moment_sum = Vec3::Zero();
  std::array<Vec2, 2> foot_moment{{Vec2::Zero(), Vec2::Zero()}};
  for (int i = 0; i < d_->ncon; ++i) {
    const mjContact& c = d_->contact[i];
    const int floor = model_->floor_geom();
    if (c.geom1 != floor && c.geom2 != floor) continue;
    const int robot_geom = c.geom1 == floor ? c.geom2 : c.geom1;
    mjtNum f6[6];
    mj_contactForce(m, d_, i, f6);
    // Contact frame rows: normal, tangent 1, tangent 2. The force acts on geom2 from geom1; flip so
    // it is the floor's force on the robot.
    Vec3 f_W = Vec3::Zero();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) f_W[k] += c.frame[3 * r + k] * f6[r];
    if (c.geom2 == floor) f_W = -f_W;
    const double fn = std::max(0.0, f_W.z());
    const Vec3 p(c.pos[0], c.pos[1], c.pos[2]);
    const int side = model_->sole_side(robot_geom);
    if (side >= 0) {
      FootContact& fc = s.feet[static_cast<std::size_t>(side)];
      fc.normal_force_n += fn;
      fc.force_W += f_W;
      foot_moment[static_cast<std::size_t>(side)] += fn * p.head<2>();
    } else {
      const int link = model_->geom_link(robot_geom);
      if (std::find(s.non_sole_links.begin(), s.non_sole_links.end(), link) == s.non_sole_links.end())
        s.non_sole_links.push_back(link);
    }
    s.normal_force_n += fn;
    moment_sum.head<2>() += fn * p.head<2>();
  }
  for (int side = 0; side < 2; ++side) {
    FootContact& fc = s.feet[static_cast<std::size_t>(side)];
    if (fc.normal_force_n > 1e-9) fc.cop_W = foot_moment[static_cast<std::size_t>(side)] / fc.normal_force_n;
  }
  if (s.normal_force_n > 1e-9) s.cop_W = moment_sum.head<2>() / s.normal_force_n;
  return s;
}

}  // namespace rt
