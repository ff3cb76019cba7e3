#include "src/refine/window_nlp.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"
#include "retarget/model/kinematics.hpp"
#include "src/refine/trajectory_chart.hpp"

namespace rt::refine {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kStanceRows = 5;  // sole centre x, y, z, normal x, y
constexpr int kFloorRows = 4;   // sole corners
// Sole centre horizontal velocity. (A vertical row too made Ipopt stall on some windows: with
// z = 0 at every stance frame, it nearly repeats the z rows of the next collocation frame.)
constexpr int kStillRows = 2;
constexpr int kStillKind = kStanceRows + kFloorRows;

// Dofs (ascending) that move a link: the dof chain from its body up to the root.
std::vector<int> link_chain(const mjModel* m, int body) {
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  std::vector<int> chain;
  for (int dof = body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1; dof >= 0; dof = m->dof_parentid[dof])
    chain.push_back(dof);
  std::sort(chain.begin(), chain.end());
  return chain;
}

Vec3 column(const MatXr& M, int c) { return Vec3(M(0, c), M(1, c), M(2, c)); }

}  // namespace

NlpRobot::NlpRobot(const RobotModel& robot_model, double limit_margin) : model(&robot_model), nv(robot_model.nv()) {
  const mjModel* m = robot_model.mj();
  chains.resize(robot_model.links().size());
  for (std::size_t l = 0; l < robot_model.links().size(); ++l) chains[l] = link_chain(m, robot_model.links()[l].body);

  pattern.assign(static_cast<std::size_t>(nv * nv), 0);
  auto add_chain = [&](int link) {
    for (int a : chains[static_cast<std::size_t>(link)])
      for (int b : chains[static_cast<std::size_t>(link)]) pattern[static_cast<std::size_t>(a * nv + b)] = 1;
  };
  for (const LandmarkTarget& lt : robot_model.config().landmarks) add_chain(robot_model.link_index(lt.link));
  moves_feet.assign(static_cast<std::size_t>(nv), 0);
  for (const Sole& s : robot_model.soles()) {
    add_chain(s.link);
    for (int d : chains[static_cast<std::size_t>(s.link)]) moves_feet[static_cast<std::size_t>(d)] = 1;
  }
  for (int i = 0; i < nv; ++i) pattern[static_cast<std::size_t>(i * nv + i)] = 1;

  // Sole normals in their links, from the soles' frames (a link's own axes may point anywhere:
  // DH-style frames).
  for (int foot = 0; foot < 2; ++foot)
    n_L_sole[static_cast<std::size_t>(foot)] = robot_model.soles()[static_cast<std::size_t>(foot)].R_L_S.col(2);

  const int nu = robot_model.nu();
  lower = VecX::Constant(nv, -kInf);
  upper = VecX::Constant(nv, kInf);
  velocity_limit = VecX::Zero(nv);
  for (int i = 0; i < nu; ++i) {
    double lo = robot_model.q_lower()[i], hi = robot_model.q_upper()[i];
    if (std::isfinite(lo) && std::isfinite(hi)) {
      const double margin = std::min(limit_margin, 0.25 * (hi - lo));
      lo += margin;
      hi -= margin;
    }
    lower[6 + i] = lo;
    upper[6 + i] = hi;
    velocity_limit[6 + i] = robot_model.velocity_limits()[i];
  }
}

WindowNlp::WindowNlp(const NlpRobot& robot, RobotData& data, const WindowSpec& spec, const NlpWeights& weights)
    : robot_(robot), data_(data), spec_(spec), weights_(weights), nv_(robot.nv) {
  size_ = static_cast<int>(spec_.controls.cols());
  RT_DEMAND(spec_.controls.rows() == nv_, "WindowNlp: control points have the wrong dimension");
  RT_DEMAND(spec_.num_pinned >= 0 && spec_.num_pinned < size_, "WindowNlp: no free control point");
  RT_DEMAND(spec_.segment_s > 0, "WindowNlp: segment duration must be positive");
  RT_DEMAND(spec_.free_coordinates.empty() || static_cast<int>(spec_.free_coordinates.size()) == nv_,
            "WindowNlp: free_coordinates has the wrong size");
  coord_var_.assign(static_cast<std::size_t>(nv_), -1);
  for (int i = 0; i < nv_; ++i)
    if (spec_.free_coordinates.empty() || spec_.free_coordinates[static_cast<std::size_t>(i)]) {
      coord_var_[static_cast<std::size_t>(i)] = num_free_coords_++;
      free_coords_.push_back(i);
    }
  RT_DEMAND(num_free_coords_ > 0, "WindowNlp: no free coordinate");
  free_chains_.resize(robot_.chains.size());
  for (std::size_t l = 0; l < robot_.chains.size(); ++l)
    for (int d : robot_.chains[l])
      if (coord_var_[static_cast<std::size_t>(d)] >= 0) free_chains_[l].push_back(d);

  num_free_ = size_ - spec_.num_pinned;
  n_ = num_free_ * num_free_coords_;
  anchor_var_.assign(spec_.anchors.size(), -1);
  for (std::size_t a = 0; a < spec_.anchors.size(); ++a)
    if (!spec_.anchors[a].fixed) {
      anchor_var_[a] = n_;
      n_ += 2;
    }
  x_lower_.resize(n_);
  x_upper_.resize(n_);
  for (int l = spec_.num_pinned; l < size_; ++l)
    for (int i : free_coords_) {
      x_lower_[var(l, i)] = robot_.lower[i];
      x_upper_[var(l, i)] = robot_.upper[i];
    }
  for (int i = num_free_ * num_free_coords_; i < n_; ++i) {
    x_lower_[i] = -kInf;
    x_upper_[i] = kInf;
  }
  for (const CollocationPoint& p : spec_.points) {
    bool any_free = false;
    for (int m = 0; m < p.support.count; ++m) {
      const int l = p.support.index[static_cast<std::size_t>(m)] - spec_.first_control;
      RT_DEMAND(l >= 0 && l < size_, "WindowNlp: collocation point outside the window");
      any_free = any_free || is_free(l);
    }
    RT_DEMAND(any_free, "WindowNlp: collocation point without a free control point");
    RT_DEMAND(p.x_ik.size() == nv_, "WindowNlp: x_ik has the wrong size");
  }
  C_ = spec_.controls;
  q_.resize(robot_.model->nq());
  xc_.resize(nv_);
  Hc_.setZero(nv_, nv_);
  gc_.resize(nv_);
  J_.resize(3, nv_);
  link_slot_.assign(robot_.model->links().size(), -1);
  build_structure();
}

double WindowNlp::max_step(int coord) const {
  return robot_.velocity_limit[coord] * spec_.segment_s * (1.0 - weights_.velocity_margin);
}

int WindowNlp::block_offset(int l1, int l2) const {
  const int d = l1 - l2;
  if (d < 0 || d > 3) return -1;
  return block_offsets_[static_cast<std::size_t>(l1 * 4 + d)];
}

void WindowNlp::build_structure() {
  // ---- constraints: velocity rows, then per point its stance / floor rows ----
  std::vector<double> lo, hi;
  auto add_entry = [&](int row, int col) {
    jac_rows_.push_back(row);
    jac_cols_.push_back(col);
  };
  for (int j = 0; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    for (int i : free_coords_) {
      if (!(robot_.velocity_limit[i] > 0)) continue;
      const double step = max_step(i);
      const bool forced = !spec_.forced_velocity_rows.empty() &&
                          spec_.forced_velocity_rows[static_cast<std::size_t>(j * nv_ + i)];
      const double used = std::abs(spec_.controls(i, j + 1) - spec_.controls(i, j));
      if (!forced && used < weights_.velocity_activation * step) continue;
      const int row = static_cast<int>(lo.size());
      lo.push_back(-step);
      hi.push_back(step);
      velocity_rows_.emplace_back(j, i);
      if (is_free(j)) add_entry(row, var(j, i));
      add_entry(row, var(j + 1, i));
    }
  }
  velocity_jac_entries_ = static_cast<int>(jac_rows_.size());
  int con_hess_size = 0;
  point_rows_.resize(spec_.points.size());
  for (std::size_t p = 0; p < spec_.points.size(); ++p) {
    const CollocationPoint& pt = spec_.points[p];
    PointRows& pr = point_rows_[p];
    pr.first_row = static_cast<int>(lo.size());
    for (int foot = 0; foot < 2; ++foot) {
      const int sole_link = robot_.model->soles()[static_cast<std::size_t>(foot)].link;
      const std::vector<int>& chain = free_chains_[static_cast<std::size_t>(sole_link)];
      const int phase = pt.stance[static_cast<std::size_t>(foot)];
      int kinds_begin = 0, kinds_end = 0;
      if (phase >= 0) {
        RT_DEMAND(phase < static_cast<int>(spec_.anchors.size()), "WindowNlp: stance phase index");
        kinds_end = kStanceRows;
      } else if (pt.floor[static_cast<std::size_t>(foot)]) {
        kinds_begin = kStanceRows;
        kinds_end = kStanceRows + kFloorRows;
      }
      if (kinds_end > kinds_begin)
        RT_DEMAND(!chain.empty(), "WindowNlp: contact rows on a foot whose coordinates are all fixed");
      std::vector<int> kinds;
      for (int kind = kinds_begin; kind < kinds_end; ++kind) kinds.push_back(kind);
      if (phase >= 0 && pt.still[static_cast<std::size_t>(foot)])
        for (int kind = kStillKind; kind < kStillKind + kStillRows; ++kind) kinds.push_back(kind);
      for (int kind : kinds) {
        const int row = static_cast<int>(lo.size());
        const int nc = static_cast<int>(chain.size());
        RowSpan rs{foot, kind, sole_link, -1, static_cast<int>(jac_rows_.size()), con_hess_size};
        if (kind < kStillKind) con_hess_size += nc * (nc + 1) / 2;
        if (kind < 2 && anchor_var_[static_cast<std::size_t>(phase)] >= 0) rs.anchor_var = anchor_var_[static_cast<std::size_t>(phase)] + kind;
        for (int m = 0; m < pt.support.count; ++m) {
          const int l = pt.support.index[static_cast<std::size_t>(m)] - spec_.first_control;
          if (!is_free(l)) continue;
          for (int d : chain) add_entry(row, var(l, d));
        }
        if (rs.anchor_var >= 0) add_entry(row, rs.anchor_var);
        if (kind < kStanceRows || kind >= kStillKind) {
          lo.push_back(0);
          hi.push_back(0);
          ++num_equalities_;
        } else {
          lo.push_back(0);
          hi.push_back(kInf);
          ++num_floor_rows_;
        }
        pr.rows.push_back(rs);
      }
    }
  }
  m_ = static_cast<int>(lo.size());
  con_hess_ = VecX::Zero(con_hess_size);
  g_lower_ = Eigen::Map<VecX>(lo.data(), m_);
  g_upper_ = Eigen::Map<VecX>(hi.data(), m_);
  for (std::size_t a = 0; a < spec_.anchors.size(); ++a)
    if (anchor_var_[a] >= 0) {
      bool used = false;
      for (const PointRows& pr : point_rows_)
        for (const RowSpan& rs : pr.rows) used = used || rs.anchor_var == anchor_var_[a];
      RT_DEMAND(used, "WindowNlp: a free stance anchor without stance rows");
    }

  // ---- Hessian: blocks between free control points that share a point or an acceleration term ----
  for (int i : free_coords_)
    for (int k : free_coords_)
      if (robot_.pattern[static_cast<std::size_t>(i * nv_ + k)]) {
        if (i == k) diag_full_.push_back(static_cast<int>(pattern_full_.size()));
        pattern_full_.emplace_back(i, k);
        if (i >= k) {
          if (i == k) diag_lower_.push_back(static_cast<int>(pattern_lower_.size()));
          pattern_lower_.emplace_back(i, k);
        }
      }
  std::vector<std::uint8_t> present(static_cast<std::size_t>(size_ * 4), 0);
  auto mark = [&](int l1, int l2) {
    if (l1 < l2) std::swap(l1, l2);
    if (is_free(l1) && is_free(l2) && l1 - l2 <= 3) present[static_cast<std::size_t>(l1 * 4 + (l1 - l2))] = 1;
  };
  for (const CollocationPoint& pt : spec_.points)
    for (int a = 0; a < pt.support.count; ++a)
      for (int b = 0; b <= a; ++b)
        mark(pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control,
             pt.support.index[static_cast<std::size_t>(b)] - spec_.first_control);
  for (int j = 1; j + 1 < size_; ++j)
    for (int a = j - 1; a <= j + 1; ++a)
      for (int b = j - 1; b <= a; ++b) mark(a, b);
  for (int l = spec_.num_pinned; l < size_; ++l) mark(l, l);  // every free variable has its diagonal
  block_offsets_.assign(static_cast<std::size_t>(size_ * 4), -1);
  for (int l1 = 0; l1 < size_; ++l1)
    for (int l2 = std::max(0, l1 - 3); l2 <= l1; ++l2) {
      if (!present[static_cast<std::size_t>(l1 * 4 + (l1 - l2))]) continue;
      block_offsets_[static_cast<std::size_t>(l1 * 4 + (l1 - l2))] = static_cast<int>(hess_rows_.size());
      for (const auto& [i, k] : l1 == l2 ? pattern_lower_ : pattern_full_) {
        hess_rows_.push_back(var(l1, i));
        hess_cols_.push_back(var(l2, k));
      }
    }
  grad_.resize(n_);
  g_.resize(m_);
  jac_.resize(static_cast<Eigen::Index>(jac_rows_.size()));
  hess_.resize(static_cast<Eigen::Index>(hess_rows_.size()));
}

VecX WindowNlp::initial_point() const {
  VecX x(n_);
  for (int l = spec_.num_pinned; l < size_; ++l)
    for (int i : free_coords_) x[var(l, i)] = spec_.controls(i, l);
  for (std::size_t a = 0; a < spec_.anchors.size(); ++a)
    if (anchor_var_[a] >= 0) x.segment<2>(anchor_var_[a]) = spec_.anchors[a].p_W;
  return x;
}

void WindowNlp::set_controls(const double* x) {
  for (int l = spec_.num_pinned; l < size_; ++l)
    for (int i : free_coords_) C_(i, l) = x[var(l, i)];
}

MatX WindowNlp::controls(const double* x) const {
  MatX C = spec_.controls;
  for (int l = spec_.num_pinned; l < size_; ++l)
    for (int i : free_coords_) C(i, l) = x[var(l, i)];
  return C;
}

std::vector<StanceAnchor> WindowNlp::anchors(const double* x) const {
  std::vector<StanceAnchor> out = spec_.anchors;
  for (std::size_t a = 0; a < out.size(); ++a)
    if (anchor_var_[a] >= 0) out[a].p_W = Vec2(x[anchor_var_[a]], x[anchor_var_[a] + 1]);
  return out;
}

std::vector<int> WindowNlp::velocity_rows_above(const MatX& C, double fraction, double tolerance) const {
  std::vector<int> out;
  for (int j = 0; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    for (int i : free_coords_)
      if (robot_.velocity_limit[i] > 0 && std::abs(C(i, j + 1) - C(i, j)) > fraction * max_step(i) + tolerance) out.push_back(j * nv_ + i);
  }
  return out;
}

const WindowNlp::LinkJacobian& WindowNlp::link_jacobian(int link, bool need_jacobian) {
  int& slot = link_slot_[static_cast<std::size_t>(link)];
  if (slot >= 0) return link_cache_[static_cast<std::size_t>(slot)];
  slot = num_used_links_++;
  if (slot >= static_cast<int>(link_cache_.size())) {
    link_cache_.emplace_back();
    link_cache_.back().jp.resize(3, nv_);
    link_cache_.back().jr.resize(3, nv_);
  }
  LinkJacobian& L = link_cache_[static_cast<std::size_t>(slot)];
  L.link = link;
  const int body = robot_.model->links()[static_cast<std::size_t>(link)].body;
  L.p_W_origin = Eigen::Map<const Vec3>(data_.mj()->xpos + 3 * body);
  if (need_jacobian) {
    mj_jac(robot_.model->mj(), data_.mj(), L.jp.data(), L.jr.data(), L.p_W_origin.data(), body);
    // Chart columns: the root's rotational dofs 3..5 become (ψ, a, b).
    const Mat3 M = root_rate_matrix(xc_[4], xc_[5]);
    L.jp.middleCols<3>(3) = (L.jp.middleCols<3>(3) * M).eval();
    L.jr.middleCols<3>(3) = (L.jr.middleCols<3>(3) * M).eval();
  }
  return L;
}

void WindowNlp::scatter_point_block(const CollocationPoint& pt, double* values) const {
  for (int a = 0; a < pt.support.count; ++a) {
    const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
    if (!is_free(la)) continue;
    const double wa = pt.support.weight[static_cast<std::size_t>(a)];
    for (int b = 0; b <= a; ++b) {
      const int lb = pt.support.index[static_cast<std::size_t>(b)] - spec_.first_control;
      if (!is_free(lb)) continue;
      const double s = wa * pt.support.weight[static_cast<std::size_t>(b)];
      const auto& list = la == lb ? pattern_lower_ : pattern_full_;
      double* h = values + block_offset(la, lb);
      for (std::size_t e = 0; e < list.size(); ++e) h[e] += s * Hc_(list[e].first, list[e].second);
    }
  }
}

double WindowNlp::evaluate_point(int p, bool derivatives, double* residuals, int* num_residuals) {
  const CollocationPoint& pt = spec_.points[static_cast<std::size_t>(p)];
  const RobotModel& model = *robot_.model;
  xc_.setZero();
  for (int m = 0; m < pt.support.count; ++m)
    xc_ += pt.support.weight[static_cast<std::size_t>(m)] * C_.col(pt.support.index[static_cast<std::size_t>(m)] - spec_.first_control);
  q_from_chart(xc_, q_);
  update_kinematics(model, data_, q_);
  if (derivatives) root_omega_derivatives(xc_[3], xc_[4], xc_[5], dw_);
  for (int k = 0; k < num_used_links_; ++k) link_slot_[static_cast<std::size_t>(link_cache_[static_cast<std::size_t>(k)].link)] = -1;
  num_used_links_ = 0;

  double cost = 0;
  int nr = 0;  // residuals written
  if (derivatives) {
    for (int i : free_coords_)
      for (int k : free_coords_) Hc_(i, k) = 0;
    gc_.setZero();
  }
  // Adds w·Jᵀr and w·JᵀJ (upper triangle) over a free chain; J_ holds the chain's columns.
  auto accumulate = [&](const std::vector<int>& chain, const Vec3& r, double w) {
    const int nc = static_cast<int>(chain.size());
    for (int a = 0; a < nc; ++a) {
      const int da = chain[static_cast<std::size_t>(a)];
      gc_[da] += w * J_.col(a).dot(r);
      for (int b = a; b < nc; ++b) Hc_(da, chain[static_cast<std::size_t>(b)]) += w * J_.col(a).dot(J_.col(b));
    }
  };

  for (const IkTarget& t : pt.targets) {
    if (t.weight <= 0 && t.orientation_weight <= 0) continue;
    const Iso3 X = link_pose(model, data_, t.link);
    const std::vector<int>& chain = free_chains_[static_cast<std::size_t>(t.link)];
    const bool with_derivatives = derivatives && !chain.empty();
    const LinkJacobian& L = link_jacobian(t.link, with_derivatives);
    if (t.weight > 0) {
      const Vec3 p_W = X * t.p_L;
      const Vec3 r = p_W - t.p_W;
      cost += 0.5 * t.weight * r.squaredNorm();
      if (residuals) {
        Eigen::Map<Vec3>(residuals + nr) = std::sqrt(t.weight) * r;
        nr += 3;
      }
      if (with_derivatives) {
        const Vec3 op = p_W - L.p_W_origin;
        for (std::size_t a = 0; a < chain.size(); ++a)
          J_.col(static_cast<Eigen::Index>(a)) = column(L.jp, chain[a]) - op.cross(column(L.jr, chain[a]));
        accumulate(chain, r, t.weight);
      }
    }
    if (t.orientation_weight > 0) {
      const Vec3 r = so3_log(X.linear() * t.R_L_frame * t.R_W.toRotationMatrix().transpose());
      cost += 0.5 * t.orientation_weight * r.squaredNorm();
      if (residuals) {
        Eigen::Map<Vec3>(residuals + nr) = std::sqrt(t.orientation_weight) * r;
        nr += 3;
      }
      if (with_derivatives) {
        // Rotating the link by δω (world) changes r by J_l⁻¹(r) δω.
        const Mat3 Jl_inv = so3_left_jacobian_inverse(r);
        for (std::size_t a = 0; a < chain.size(); ++a) J_.col(static_cast<Eigen::Index>(a)) = Jl_inv * column(L.jr, chain[a]);
        accumulate(chain, r, t.orientation_weight);
      }
    }
  }
  // Pull towards the per-frame IK, on the free coordinates (the others are constants here).
  for (int i : free_coords_) {
    const double r = xc_[i] - pt.x_ik[i];
    cost += 0.5 * weights_.pull * r * r;
    if (residuals) residuals[nr++] = std::sqrt(weights_.pull) * r;
    if (derivatives) {
      gc_[i] += weights_.pull * r;
      Hc_(i, i) += weights_.pull;
    }
  }
  if (num_residuals) *num_residuals = nr;

  // Scatter the point's gradient and Hessian block onto its control points.
  if (derivatives) {
    for (int i : free_coords_)
      for (int k : free_coords_)
        if (k < i) Hc_(i, k) = Hc_(k, i);
    for (int a = 0; a < pt.support.count; ++a) {
      const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
      if (!is_free(la)) continue;
      const double wa = pt.support.weight[static_cast<std::size_t>(a)];
      for (int i : free_coords_) grad_[var(la, i)] += wa * gc_[i];
    }
    scatter_point_block(pt, hess_.data());
  }

  // Constraint rows: value, first derivatives (Jacobian entries) and second derivatives.
  const PointRows& pr = point_rows_[static_cast<std::size_t>(p)];
  for (std::size_t k = 0; k < pr.rows.size(); ++k) {
    const RowSpan& rs = pr.rows[k];
    const Sole& sole = model.soles()[static_cast<std::size_t>(rs.foot)];
    const Iso3 X = link_pose(model, data_, sole.link);
    const std::vector<int>& chain = free_chains_[static_cast<std::size_t>(sole.link)];
    const LinkJacobian& L = link_jacobian(sole.link, derivatives);
    const Vec3 n = X.linear() * robot_.n_L_sole[static_cast<std::size_t>(rs.foot)];
    if (rs.kind >= kStillKind) {
      evaluate_still_row(pt, rs, X * sole.p_L_center, L, derivatives, pr.first_row + static_cast<int>(k));
      continue;
    }
    double value = 0;
    Vec3 point = Vec3::Zero();
    int axis = 2;
    const bool normal = rs.kind >= 3 && rs.kind < kStanceRows;
    if (rs.kind < 3) {
      point = X * sole.p_L_center;
      axis = rs.kind;
      value = point[axis];
      if (rs.kind < 2 && rs.anchor_var < 0) {
        const int phase = pt.stance[static_cast<std::size_t>(rs.foot)];
        value -= spec_.anchors[static_cast<std::size_t>(phase)].p_W[rs.kind];  // a variable anchor: evaluate()
      }
    } else if (normal) {
      axis = rs.kind - 3;
      value = n[axis];
    } else {
      point = X * sole.corners_L()[static_cast<std::size_t>(rs.kind - kStanceRows)];
      value = point.z();
    }
    g_[pr.first_row + static_cast<int>(k)] = value;
    if (!derivatives) continue;
    // ∂g/∂x_d: a point moves by v_d + ω_d × (p − o_d), the normal turns by ω_d × n.
    const Vec3 op = point - L.p_W_origin;
    const Vec3 base = normal ? n : Vec3(point - xc_.head<3>());  // what the root rotation turns
    const int nc = static_cast<int>(chain.size());
    double* h2 = con_hess_.data() + rs.hess_offset;
    int off = rs.value_offset;
    for (int b = 0; b < nc; ++b) {
      const int j = chain[static_cast<std::size_t>(b)];
      const Vec3 wj = column(L.jr, j);
      const Vec3 Dj = normal ? Vec3(wj.cross(n)) : Vec3(column(L.jp, j) - op.cross(wj));
      // Second derivatives: moving dof i (up the chain from j) turns everything below it, so
      // ∂²g/∂x_i∂x_j = ω_i × ∂g/∂x_j; the root tilt pair (a, b) adds the chart's own curvature.
      for (int a = 0; a <= b; ++a) {
        const int i = chain[static_cast<std::size_t>(a)];
        double v = 0;
        if (i >= 3) {
          const Vec3 wi = column(L.jr, i);
          if (i >= 4 && j <= 5)
            v = (dw_[static_cast<std::size_t>((i - 4) * 2 + (j - 4))].cross(base) + wj.cross(wi.cross(base)))[axis];
          else
            v = wi.cross(Dj)[axis];
        }
        h2[b * (b + 1) / 2 + a] = v;
      }
    }
    for (int a = 0; a < pt.support.count; ++a) {
      const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
      if (!is_free(la)) continue;
      const double wa = pt.support.weight[static_cast<std::size_t>(a)];
      for (int b = 0; b < nc; ++b) {
        const int j = chain[static_cast<std::size_t>(b)];
        const Vec3 wj = column(L.jr, j);
        const double d = normal ? wj.cross(n)[axis] : (column(L.jp, j) - op.cross(wj))[axis];
        jac_[off++] = wa * d;
      }
    }
    if (rs.anchor_var >= 0) jac_[off++] = -1.0;
  }
  return cost;
}

// Second derivative ∂²p/∂x_i∂x_j of a point for i up the chain from j (or i = j), world frame.
Vec3 WindowNlp::point_second_derivative(const LinkJacobian& L, const Vec3& op, const Vec3& r_root, int i, int j) const {
  if (i < 3) return Vec3::Zero();  // root translation: derivatives do not depend on it
  const Vec3 wi = column(L.jr, i), wj = column(L.jr, j);
  if (i >= 4 && j <= 5) return dw_[static_cast<std::size_t>((i - 4) * 2 + (j - 4))].cross(r_root) + wj.cross(wi.cross(r_root));
  return wi.cross(column(L.jp, j) - op.cross(wj));
}

void WindowNlp::evaluate_still_row(const CollocationPoint& pt, const RowSpan& rs, const Vec3& point, const LinkJacobian& L,
                                   bool derivatives, int row) {
  // v = Σ_j ∂p/∂x_j ẋ_j with ẋ = Σ_a β'_a C_a / h (chart rates per second).
  const std::vector<int>& full_chain = robot_.chains[static_cast<std::size_t>(rs.chain_link)];
  const int axis = rs.kind - kStillKind;
  const Vec3 op = point - L.p_W_origin, r_root = point - xc_.head<3>();
  VecX& xdot = gc_;  // workspace (the objective part of this point is done)
  xdot.setZero();
  for (int m = 0; m < pt.support.count; ++m)
    xdot += (pt.support.dweight[static_cast<std::size_t>(m)] / spec_.segment_s) *
            C_.col(pt.support.index[static_cast<std::size_t>(m)] - spec_.first_control);
  double v = 0;
  for (int j : full_chain) v += (column(L.jp, j) - op.cross(column(L.jr, j)))[axis] * xdot[j];
  g_[row] = v;
  if (!derivatives) return;
  // ∂v/∂C_{a,i} = β'_a/h ∂p/∂x_i + β_a Σ_j ∂²p/∂x_i∂x_j ẋ_j.
  const std::vector<int>& chain = free_chains_[static_cast<std::size_t>(rs.chain_link)];
  std::array<double, 64> d_first{}, d_second{};
  RT_DEMAND(chain.size() <= d_first.size(), "WindowNlp: kinematic chain too long");
  for (std::size_t c = 0; c < chain.size(); ++c) {
    const int i = chain[c];
    d_first[c] = (column(L.jp, i) - op.cross(column(L.jr, i)))[axis];
    double s = 0;
    for (int j : full_chain) s += (i <= j ? point_second_derivative(L, op, r_root, i, j) : point_second_derivative(L, op, r_root, j, i))[axis] * xdot[j];
    d_second[c] = s;
  }
  int off = rs.value_offset;
  for (int a = 0; a < pt.support.count; ++a) {
    const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
    if (!is_free(la)) continue;
    const double wa = pt.support.weight[static_cast<std::size_t>(a)];
    const double da = pt.support.dweight[static_cast<std::size_t>(a)] / spec_.segment_s;
    for (std::size_t c = 0; c < chain.size(); ++c) jac_[off++] = da * d_first[c] + wa * d_second[c];
  }
}

void WindowNlp::lagrangian_hessian(double obj_factor, const double* lambda, double* values, bool convexify) {
  for (Eigen::Index e = 0; e < hess_.size(); ++e) values[e] = obj_factor * hess_[e];
  for (std::size_t p = 0; p < point_rows_.size(); ++p) {
    const PointRows& pr = point_rows_[p];
    if (pr.rows.empty()) continue;
    // Sum Σ λ ∇²g per foot on the compact chain block (rows of one foot share its chain).
    for (int foot = 0; foot < 2; ++foot) {
      const int link = robot_.model->soles()[static_cast<std::size_t>(foot)].link;
      const std::vector<int>& chain = free_chains_[static_cast<std::size_t>(link)];
      const int nc = static_cast<int>(chain.size());
      MatX& B = chain_block_;
      B.setZero(nc, nc);
      bool any = false;
      for (std::size_t k = 0; k < pr.rows.size(); ++k) {
        if (pr.rows[k].foot != foot || pr.rows[k].kind >= kStillKind) continue;
        const double l = lambda[pr.first_row + static_cast<int>(k)];
        if (l == 0) continue;
        any = true;
        const double* h2 = con_hess_.data() + pr.rows[k].hess_offset;
        for (int b = 0; b < nc; ++b)
          for (int a = 0; a <= b; ++a) B(a, b) += l * h2[b * (b + 1) / 2 + a];
      }
      if (!any) continue;
      B.triangularView<Eigen::StrictlyLower>() = B.transpose();
      if (convexify) {
        eigen_.compute(B);
        B = eigen_.eigenvectors() * eigen_.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen_.eigenvectors().transpose();
      }
      for (int i : free_coords_)
        for (int k : free_coords_) Hc_(i, k) = 0;
      for (int b = 0; b < nc; ++b)
        for (int a = 0; a < nc; ++a) Hc_(chain[static_cast<std::size_t>(a)], chain[static_cast<std::size_t>(b)]) = B(a, b);
      scatter_point_block(spec_.points[p], values);
    }
  }
}

void WindowNlp::evaluate(const double* x) {
  set_controls(x);
  f_ = 0;
  grad_.setZero();
  hess_.setZero();
  // Acceleration: √w (C_{j−1} − 2C_j + C_{j+1}) / h² on the free coordinates, per interior control
  // point whose triple touches a free control point.
  const double h2 = spec_.segment_s * spec_.segment_s;
  const double c[3] = {1.0 / h2, -2.0 / h2, 1.0 / h2};
  const double w = weights_.acceleration;
  for (int j = 1; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    for (std::size_t fi = 0; fi < free_coords_.size(); ++fi) {
      const int i = free_coords_[fi];
      const double a = (C_(i, j - 1) - 2.0 * C_(i, j) + C_(i, j + 1)) / h2;
      f_ += 0.5 * w * a * a;
      for (int m = 0; m < 3; ++m) {
        const int lm = j - 1 + m;
        if (!is_free(lm)) continue;
        grad_[var(lm, i)] += w * c[m] * a;
        for (int k = 0; k <= m; ++k) {
          const int lk = j - 1 + k;
          if (!is_free(lk)) continue;
          const std::vector<int>& diag = lm == lk ? diag_lower_ : diag_full_;
          hess_[block_offset(lm, lk) + diag[fi]] += w * c[m] * c[k];
        }
      }
    }
  }
  // Velocity rows (linear).
  for (std::size_t r = 0; r < velocity_rows_.size(); ++r) {
    const auto [j, i] = velocity_rows_[r];
    g_[static_cast<Eigen::Index>(r)] = C_(i, j + 1) - C_(i, j);
  }
  for (int e = 0, r = 0; e < velocity_jac_entries_; ++r) {
    const int j = velocity_rows_[static_cast<std::size_t>(r)].first;
    if (is_free(j)) jac_[e++] = -1.0;
    jac_[e++] = 1.0;
  }
  for (int p = 0; p < static_cast<int>(spec_.points.size()); ++p) f_ += evaluate_point(p, true, nullptr, nullptr);
  // Variable anchors enter the stance x/y rows as −anchor.
  for (const PointRows& pr : point_rows_)
    for (std::size_t k = 0; k < pr.rows.size(); ++k)
      if (pr.rows[k].anchor_var >= 0) g_[pr.first_row + static_cast<int>(k)] -= x[pr.rows[k].anchor_var];
}

VecX WindowNlp::residuals(const double* x) {
  set_controls(x);
  std::vector<double> r;
  const double h2 = spec_.segment_s * spec_.segment_s;
  const double sw = std::sqrt(weights_.acceleration);
  for (int j = 1; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    for (int i : free_coords_) r.push_back(sw * (C_(i, j - 1) - 2.0 * C_(i, j) + C_(i, j + 1)) / h2);
  }
  std::vector<double> buffer(static_cast<std::size_t>(6 * robot_.model->config().landmarks.size() + nv_ + 64));
  for (int p = 0; p < static_cast<int>(spec_.points.size()); ++p) {
    int count = 0;
    evaluate_point(p, false, buffer.data(), &count);
    r.insert(r.end(), buffer.begin(), buffer.begin() + count);
  }
  return Eigen::Map<VecX>(r.data(), static_cast<Eigen::Index>(r.size()));
}

double WindowNlp::max_violation(const double* x) const {
  double v = 0;
  for (int i = 0; i < m_; ++i) v = std::max({v, g_lower_[i] - g_[i], g_[i] - g_upper_[i]});
  for (int i = 0; i < n_; ++i) v = std::max({v, x_lower_[i] - x[i], x[i] - x_upper_[i]});
  return v;
}

}  // namespace rt::refine
