#pragma once
/// Thin kinematics/dynamics API over MuJoCo with the model/data split (style: pinocchio/mujoco
/// free functions). Call `update_kinematics` (positions only) or `update_dynamics` (positions and
/// velocities) first; the query functions read the cached results in `data`.
///
/// Jacobians are 6 x nv or 3 x nv, rows [linear; angular] in the world frame, for the generalised
/// velocity v of robot_model.hpp (root linear velocity in W, root angular velocity in the root
/// frame). `p_L` points are in the link frame.

#include <array>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/model/robot_data.hpp"

namespace rt {

/// Sets q (size nq) and runs forward kinematics + COM (mj_kinematics, mj_comPos).
void update_kinematics(const RobotModel& model, RobotData& data, const VecXCRef& q);

/// Sets q, v (nv) and computes everything the controller needs: kinematics, COM, body velocities,
/// mass matrix (and its factorisation, so mj_solveM works on data.mj()), bias forces. These are the
/// position/velocity stages of mj_forward without collision detection, constraints or actuation:
/// contacts in data.mj() are not updated.
void update_dynamics(const RobotModel& model, RobotData& data, const VecXCRef& q, const VecXCRef& v);

/// The same results as update_dynamics, copied from another mjData of this model on which MuJoCo's
/// position and velocity stages already ran for the state it holds (mj_forward, or mj_step1 at the
/// start of a simulation step): a copy instead of a second evaluation of the same functions on the
/// same inputs. The dynamics check uses it to give the controller's own data the measured state.
void assign_dynamics(const RobotModel& model, RobotData& data, const mjData& source);

/// Pose of a link in the world.
Iso3 link_pose(const RobotModel& model, const RobotData& data, int link);

/// World position of a point fixed in a link.
Vec3 link_point(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L);

/// 6 x nv Jacobian of a point fixed in a link: rows 0-2 linear velocity of the point, rows 3-5
/// angular velocity of the link, both in W.
MatX link_jacobian(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L = Vec3::Zero());

/// Whole-body centre of mass [m] in W.
Vec3 com_position(const RobotModel& model, const RobotData& data);

/// 3 x nv Jacobian of the whole-body COM (the centroidal momentum matrix's linear rows over the mass).
MatX com_jacobian(const RobotModel& model, const RobotData& data);

/// nv x nv joint-space mass matrix M(q) (after update_dynamics).
MatX mass_matrix(const RobotModel& model, const RobotData& data);

/// nv bias forces c(q, v) = Coriolis + centrifugal + gravity (after update_dynamics).
VecX bias_forces(const RobotModel& model, const RobotData& data);

/// J̇·v of a link point (6: [linear; angular], W), exact (after update_dynamics): the classical
/// acceleration of the point and the angular acceleration of the link when q̈ = 0, from MuJoCo's
/// cdof_dot (what mj_rnePostConstraint does with zero qacc, dependencies.md §5, without touching
/// data).
Vec6 link_jdot_v(const RobotModel& model, const RobotData& data, int link, const Vec3& p_L = Vec3::Zero());

/// The generalised velocities (indices into v, ascending) that move `link`: its body's dofs and its
/// ancestors'. All other columns of the link's Jacobians are structurally zero.
std::vector<int> link_dof_chain(const RobotModel& model, int link);

/// Solves M(q) X = B in place for the right-hand sides in the columns of X (nv rows, row-major),
/// with the sparse L'DL factor of M that update_dynamics leaves in data (the same result as
/// mj_solveM column by column). Each step of the tree-sparse substitution updates a whole row, which
/// vectorises: for tens of right-hand sides several times faster than mj_solveM.
void solve_mass_matrix(const RobotModel& model, const RobotData& data, Eigen::Ref<MatXr> X);

/// Integrates q by v·dt on the configuration manifold (quaternion-aware, mj_integratePos): the
/// root moves by v_W·dt and turns by ω·dt about its own axes.
VecX integrate(const RobotModel& model, const VecXCRef& q, const VecXCRef& v, double dt);

/// v such that integrate(q1, v, dt) = q2 (quaternion-aware finite difference).
VecX difference(const RobotModel& model, const VecXCRef& q1, const VecXCRef& q2, double dt);

/// Orientation of each sole frame (x forward, z the sole normal) in its foot link frame:
/// Sole::R_L_S (link axes for a sole given in robot.yaml, the standing pose's face for a derived
/// one). Leaves `data` at the zero configuration (callers rely on nothing else).
std::array<Mat3, 2> sole_frames_in_links(const RobotModel& model, RobotData& data);

/// Height [m] of the lowest corner of sole `foot` (0 left, 1 right) above the floor z = 0, at the
/// configuration last given to update_kinematics.
double lowest_sole_corner_z(const RobotModel& model, const RobotData& data, int foot);

}  // namespace rt
