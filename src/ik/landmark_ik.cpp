#include "retarget/ik/landmark_ik.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/kinematics.hpp"

namespace rt {

namespace {
Vec3 rotation_log(const Mat3& R) {
  const AngleAxis aa(R);
  return aa.angle() * aa.axis();
}

// Adds one 3-row residual block s·(J r) to the normal equations (upper triangle of H), over its
// chain's columns only (plain loops: the blocks are 3 x ≤20, far below where a GEMM pays off).
void accumulate(const MatXr& J, const Vec3& r, double s, const std::vector<int>& chain, MatX& H, VecX& g) {
  const double s2 = s * s;
  for (const int a : chain) {
    const Vec3 ja(J(0, a), J(1, a), J(2, a));
    g[a] += s2 * ja.dot(r);
    for (const int b : chain) {
      if (b < a) continue;
      H(a, b) += s2 * (ja.x() * J(0, b) + ja.y() * J(1, b) + ja.z() * J(2, b));
    }
  }
}
}  // namespace

LandmarkIk::LandmarkIk(const RobotModel& model, IkOptions options) : model_(&model), options_(options) {
  RobotData data(model);
  VecX q0 = VecX::Zero(model.nq());
  q0[3] = 1;  // identity root quaternion (w x y z)
  update_kinematics(model, data, q0);
  R_L_lm_.resize(model.links().size());
  chains_.resize(model.links().size());
  const mjModel* m = model.mj();
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    R_L_lm_[l] = link_pose(model, data, static_cast<int>(l)).linear().transpose();
    // Degrees of freedom that move this link: the dof chain from its body up to the root.
    int body = model.links()[l].body;
    while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
    std::vector<int>& chain = chains_[l];
    for (int dof = body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1; dof >= 0; dof = m->dof_parentid[dof])
      chain.push_back(dof);
    std::sort(chain.begin(), chain.end());
  }
}

Mat3 LandmarkIk::landmark_frame_in_link(int link) const { return R_L_lm_.at(static_cast<std::size_t>(link)); }

double LandmarkIk::add_targets(const RobotData& data, const std::vector<IkTarget>& targets, MatX* H, VecX* g, MatXr& jp,
                               MatXr& jr) const {
  const RobotModel& model = *model_;
  const mjModel* m = model.mj();
  double cost = 0;
  for (const IkTarget& t : targets) {
    if (t.weight <= 0 && t.orientation_weight <= 0) continue;
    const Iso3 X = link_pose(model, data, t.link);
    const Vec3 p_W = X * t.p_L;
    const int body = model.links()[static_cast<std::size_t>(t.link)].body;
    if (H) mj_jac(m, data.mj(), jp.data(), jr.data(), p_W.data(), body);
    const std::vector<int>& chain = chains_[static_cast<std::size_t>(t.link)];
    if (t.weight > 0) {
      const Vec3 r = p_W - t.p_W;
      cost += 0.5 * t.weight * r.squaredNorm();
      if (H) accumulate(jp, r, std::sqrt(t.weight), chain, *H, *g);
    }
    if (t.orientation_weight > 0) {
      // r = log(R_now R_targetᵀ): rotating the link by δω changes r by ≈ δω (Gauss–Newton).
      const Vec3 r = rotation_log(X.linear() * t.R_L_frame * t.R_W.toRotationMatrix().transpose());
      cost += 0.5 * t.orientation_weight * r.squaredNorm();
      if (H) accumulate(jr, r, std::sqrt(t.orientation_weight), chain, *H, *g);
    }
  }
  return cost;
}

MatX LandmarkIk::targets_normal_matrix(RobotData& data, const std::vector<IkTarget>& targets, const VecX& q) const {
  const int nv = model_->nv();
  update_kinematics(*model_, data, q);
  MatX H = MatX::Zero(nv, nv);
  VecX g = VecX::Zero(nv);
  MatXr jp(3, nv), jr(3, nv);
  add_targets(data, targets, &H, &g, jp, jr);
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
  return H;
}

IkResult LandmarkIk::solve(RobotData& data, const std::vector<IkTarget>& targets, const VecX& q_prev, VecX& q,
                           const IkComTarget& com, const IkFloorTerm& floor, const IkJointBounds* bounds) const {
  const RobotModel& model = *model_;
  const mjModel* m = model.mj();
  const int nv = model.nv(), nu = model.nu();
  RT_DEMAND(q.size() == model.nq() && q_prev.size() == model.nq(), "LandmarkIk::solve: configuration size");
  VecX lo = model.q_lower().array() + options_.joint_limit_margin;
  VecX hi = model.q_upper().array() - options_.joint_limit_margin;
  if (bounds) {
    RT_DEMAND(bounds->lower.size() == nu && bounds->upper.size() == nu, "LandmarkIk::solve: bounds size");
    // An empty intersection (a bound outside the URDF range) collapses onto the URDF limit.
    lo = lo.cwiseMax(bounds->lower.cwiseMin(hi));
    hi = hi.cwiseMin(bounds->upper.cwiseMax(lo));
  }
  for (int i = 0; i < nu; ++i) q[7 + i] = std::clamp(q[7 + i], std::min(lo[i], hi[i]), std::max(lo[i], hi[i]));

  const double reg = options_.regularization;
  const VecX& factors = options_.regularization_factors;
  const bool per_dof = factors.size() == nv;
  RT_DEMAND(per_dof || factors.size() == 0, "LandmarkIk: regularization_factors must have nv entries");
  MatXr jp(3, nv), jr(3, nv);
  std::vector<FloorPenalty> penalties;

  // The configuration whose kinematics `data` holds: the solver evaluates an accepted trial point a
  // second time, with derivatives, and the kinematics are most of an evaluation's cost.
  VecX at;
  auto kinematics_at = [&](const VecX& x) {
    if (at.size() == x.size() && at == x) return;
    update_kinematics(model, data, x);
    at = x;
  };
  LeastSquaresProblem problem;
  problem.tangent_size = nv;
  problem.evaluate = [&](const VecX& x, MatX* H, VecX* g) {
    kinematics_at(x);
    if (H) {
      H->setZero(nv, nv);
      g->setZero(nv);
    }
    double cost = add_targets(data, targets, H, g, jp, jr);
    if (com.weight > 0) {
      const int rows = com.horizontal_only ? 2 : 3;
      const Vec3 e = com_position(model, data) - com.p_W;
      cost += 0.5 * com.weight * e.head(rows).squaredNorm();
      if (H) {
        const MatX Jc = com_jacobian(model, data).topRows(rows);
        H->triangularView<Eigen::Upper>() += com.weight * (Jc.transpose() * Jc);
        *g += com.weight * Jc.transpose() * e.head(rows);
      }
    }
    if (floor.weight > 0) {
      penalties.clear();
      floor_penalties(model, data, floor.weight, floor.link_min_height_m, floor.skip_links, penalties);
      for (const FloorPenalty& pen : penalties) {
        cost += pen.cost;
        if (!H) continue;
        mj_jac(m, data.mj(), jp.data(), jr.data(), pen.p_W_origin.data(), model.links()[static_cast<std::size_t>(pen.link)].body);
        const std::vector<int>& chain = chains_[static_cast<std::size_t>(pen.link)];
        // B = [J_p,z; J_ω,x; J_ω,y] over the chain: H += Bᵀ M B, g += Bᵀ m.
        for (const int a : chain) {
          const Vec3 ba(jp(2, a), jr(0, a), jr(1, a));
          (*g)[a] += ba.dot(pen.m);
          const Vec3 Mba = pen.M * ba;
          for (const int c : chain)
            if (c >= a) (*H)(a, c) += Mba.dot(Vec3(jp(2, c), jr(0, c), jr(1, c)));
        }
      }
    }
    const VecX d = difference(model, q_prev, x, 1.0);
    if (per_dof) {
      cost += 0.5 * reg * d.dot(factors.cwiseProduct(d));
    } else {
      cost += 0.5 * reg * d.squaredNorm();
    }
    if (H) {
      if (per_dof) {
        H->diagonal() += reg * factors;
        *g += reg * factors.cwiseProduct(d);
      } else {
        H->diagonal().array() += reg;
        *g += reg * d;
      }
      H->triangularView<Eigen::StrictlyLower>() = H->transpose();  // blocks filled the upper triangle
    }
    return cost;
  };
  problem.retract = [&](const VecX& x, const VecX& delta) { return integrate(model, x, delta, 1.0); };
  problem.step_bounds = [&](const VecX& x, VecX& lower, VecX& upper) {
    lower.resize(nv);
    upper.resize(nv);
    for (int i = 0; i < 6; ++i) {
      lower[i] = options_.root_free[static_cast<std::size_t>(i)] ? -INFINITY : 0.0;
      upper[i] = options_.root_free[static_cast<std::size_t>(i)] ? INFINITY : 0.0;
    }
    lower.tail(nu) = (lo - x.tail(nu)).cwiseMin(0.0);
    upper.tail(nu) = (hi - x.tail(nu)).cwiseMax(0.0);
  };

  BoundedLmOptions lm;
  lm.max_iterations = options_.max_iterations;
  lm.step_tolerance = options_.step_tolerance;
  lm.cost_tolerance = options_.cost_tolerance;
  lm.initial_damping = options_.initial_damping;
  IkResult result;
  result.solver = solve_bounded_lm(problem, q, lm);

  // Report position errors at the solution.
  kinematics_at(q);
  double weighted = 0, weights = 0;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const IkTarget& t = targets[i];
    if (t.weight <= 0) continue;
    const double e = (link_point(model, data, t.link, t.p_L) - t.p_W).norm();
    weighted += t.weight * e * e;
    weights += t.weight;
    if (e > result.max_error_m) {
      result.max_error_m = e;
      result.worst_target = static_cast<int>(i);
    }
  }
  result.rms_error_m = weights > 0 ? std::sqrt(weighted / weights) : 0;
  return result;
}

}  // namespace rt
