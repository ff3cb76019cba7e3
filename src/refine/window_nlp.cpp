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

// Dofs (ascending) that move a link: the dof chain from its body up to the root.
std::vector<int> link_chain(const mjModel* m, int body) {
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  std::vector<int> chain;
  for (int dof = body > 0 ? m->body_dofadr[body] + m->body_dofnum[body] - 1 : -1; dof >= 0; dof = m->dof_parentid[dof])
    chain.push_back(dof);
  std::sort(chain.begin(), chain.end());
  return chain;
}

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
  for (const Sole& s : robot_model.soles()) add_chain(s.link);
  for (int i = 0; i < nv; ++i) pattern[static_cast<std::size_t>(i * nv + i)] = 1;

  // Sole normals: at the zero configuration every foot frame is world aligned (robot.yaml convention).
  RobotData data(robot_model);
  VecX q0 = VecX::Zero(robot_model.nq());
  q0[3] = 1;
  update_kinematics(robot_model, data, q0);
  for (int foot = 0; foot < 2; ++foot)
    n_L_sole[static_cast<std::size_t>(foot)] =
        link_pose(robot_model, data, robot_model.soles()[static_cast<std::size_t>(foot)].link).linear().transpose() * Vec3::UnitZ();

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
  num_free_ = size_ - spec_.num_pinned;
  n_ = num_free_ * nv_;
  anchor_var_.assign(spec_.anchors.size(), -1);
  for (std::size_t a = 0; a < spec_.anchors.size(); ++a)
    if (!spec_.anchors[a].fixed) {
      anchor_var_[a] = n_;
      n_ += 2;
    }
  x_lower_.resize(n_);
  x_upper_.resize(n_);
  for (int l = spec_.num_pinned; l < size_; ++l) {
    x_lower_.segment(var(l, 0), nv_) = robot_.lower;
    x_upper_.segment(var(l, 0), nv_) = robot_.upper;
  }
  for (int i = num_free_ * nv_; i < n_; ++i) {
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
  }
  C_ = spec_.controls;
  q_.resize(robot_.model->nq());
  xc_.resize(nv_);
  Hc_.resize(nv_, nv_);
  gc_.resize(nv_);
  J_.resize(3, nv_);
  link_slot_.assign(robot_.model->links().size(), -1);
  build_structure();
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
    for (int i = 0; i < nv_; ++i) {
      const double v = robot_.velocity_limit[i];
      if (!(v > 0)) continue;
      const int row = static_cast<int>(lo.size());
      const double step = v * spec_.segment_s * (1.0 - weights_.velocity_margin);
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
      const int phase = pt.stance[static_cast<std::size_t>(foot)];
      int kinds_begin = 0, kinds_end = 0;
      if (phase >= 0) {
        RT_DEMAND(phase < static_cast<int>(spec_.anchors.size()), "WindowNlp: stance phase index");
        kinds_end = kStanceRows;
      } else if (pt.floor[static_cast<std::size_t>(foot)]) {
        kinds_begin = kStanceRows;
        kinds_end = kStanceRows + kFloorRows;
      }
      for (int kind = kinds_begin; kind < kinds_end; ++kind) {
        const int row = static_cast<int>(lo.size());
        const int nc = static_cast<int>(robot_.chains[static_cast<std::size_t>(sole_link)].size());
        RowSpan rs{foot, kind, sole_link, -1, static_cast<int>(jac_rows_.size()), con_hess_size};
        con_hess_size += nc * (nc + 1) / 2;
        if (kind < 2 && anchor_var_[static_cast<std::size_t>(phase)] >= 0) rs.anchor_var = anchor_var_[static_cast<std::size_t>(phase)] + kind;
        for (int m = 0; m < pt.support.count; ++m) {
          const int l = pt.support.index[static_cast<std::size_t>(m)] - spec_.first_control;
          if (!is_free(l)) continue;
          for (int d : robot_.chains[static_cast<std::size_t>(sole_link)]) add_entry(row, var(l, d));
        }
        if (rs.anchor_var >= 0) add_entry(row, rs.anchor_var);
        if (kind < kStanceRows) {
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

  // ---- Hessian: blocks between free control points that share a point or an acceleration term ----
  for (int i = 0; i < nv_; ++i)
    for (int k = 0; k < nv_; ++k)
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
  for (int l = spec_.num_pinned; l < size_; ++l) x.segment(var(l, 0), nv_) = spec_.controls.col(l);
  for (std::size_t a = 0; a < spec_.anchors.size(); ++a)
    if (anchor_var_[a] >= 0) x.segment<2>(anchor_var_[a]) = spec_.anchors[a].p_W;
  return x;
}

void WindowNlp::set_controls(const double* x) {
  for (int l = spec_.num_pinned; l < size_; ++l) C_.col(l) = Eigen::Map<const VecX>(x + var(l, 0), nv_);
}

MatX WindowNlp::controls(const double* x) const {
  MatX C = spec_.controls;
  for (int l = spec_.num_pinned; l < size_; ++l) C.col(l) = Eigen::Map<const VecX>(x + var(l, 0), nv_);
  return C;
}

std::vector<StanceAnchor> WindowNlp::anchors(const double* x) const {
  std::vector<StanceAnchor> out = spec_.anchors;
  for (std::size_t a = 0; a < out.size(); ++a)
    if (anchor_var_[a] >= 0) out[a].p_W = Vec2(x[anchor_var_[a]], x[anchor_var_[a] + 1]);
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
  const mjData* d = data_.mj();
  L.p_W_origin = Eigen::Map<const Vec3>(d->xpos + 3 * body);
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
    Hc_.setZero();
    gc_.setZero();
  }
  // Adds w·(J r) and w·JᵀJ over a chain, J given by a column function (3 x chain).
  Mat3X& J = J_;
  auto accumulate = [&](const std::vector<int>& chain, const Vec3& r, double w) {
    const int nc = static_cast<int>(chain.size());
    for (int a = 0; a < nc; ++a) {
      const int da = chain[static_cast<std::size_t>(a)];
      gc_[da] += w * J.col(a).dot(r);
      for (int b = a; b < nc; ++b) Hc_(da, chain[static_cast<std::size_t>(b)]) += w * J.col(a).dot(J.col(b));
    }
  };

  for (const IkTarget& t : pt.targets) {
    if (t.weight <= 0 && t.orientation_weight <= 0) continue;
    const Iso3 X = link_pose(model, data_, t.link);
    const std::vector<int>& chain = robot_.chains[static_cast<std::size_t>(t.link)];
    const LinkJacobian& L = link_jacobian(t.link, derivatives);
    if (t.weight > 0) {
      const Vec3 p_W = X * t.p_L;
      const Vec3 r = p_W - t.p_W;
      cost += 0.5 * t.weight * r.squaredNorm();
      if (residuals) {
        Eigen::Map<Vec3>(residuals + nr) = std::sqrt(t.weight) * r;
        nr += 3;
      }
      if (derivatives) {
        const Vec3 op = p_W - L.p_W_origin;
        for (std::size_t a = 0; a < chain.size(); ++a) {
          const int d = chain[a];
          J.col(static_cast<Eigen::Index>(a)) = Vec3(L.jp(0, d), L.jp(1, d), L.jp(2, d)) - op.cross(Vec3(L.jr(0, d), L.jr(1, d), L.jr(2, d)));
        }
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
      if (derivatives) {
        // Rotating the link by δω (world) changes r by J_l⁻¹(r) δω.
        const Mat3 Jl_inv = so3_left_jacobian_inverse(r);
        for (std::size_t a = 0; a < chain.size(); ++a) {
          const int d = chain[a];
          J.col(static_cast<Eigen::Index>(a)) = Jl_inv * Vec3(L.jr(0, d), L.jr(1, d), L.jr(2, d));
        }
        accumulate(chain, r, t.orientation_weight);
      }
    }
  }
  {
    const VecX r = xc_ - pt.x_ik;
    cost += 0.5 * weights_.pull * r.squaredNorm();
    if (residuals) {
      Eigen::Map<VecX>(residuals + nr, nv_) = std::sqrt(weights_.pull) * r;
      nr += nv_;
    }
    if (derivatives) {
      gc_ += weights_.pull * r;
      Hc_.diagonal().array() += weights_.pull;
    }
  }
  if (num_residuals) *num_residuals = nr;

  // Scatter the point's gradient and Hessian block onto its control points.
  if (derivatives) {
    Hc_.triangularView<Eigen::StrictlyLower>() = Hc_.transpose();
    for (int a = 0; a < pt.support.count; ++a) {
      const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
      if (is_free(la)) grad_.segment(var(la, 0), nv_) += pt.support.weight[static_cast<std::size_t>(a)] * gc_;
    }
    scatter_point_block(pt, hess_.data());
  }

  // Constraint rows.
  const PointRows& pr = point_rows_[static_cast<std::size_t>(p)];
  if (!pr.rows.empty()) {
    Eigen::RowVectorXd row(nv_);
    for (std::size_t k = 0; k < pr.rows.size(); ++k) {
      const RowSpan& rs = pr.rows[k];
      const Sole& sole = model.soles()[static_cast<std::size_t>(rs.foot)];
      const Iso3 X = link_pose(model, data_, sole.link);
      const std::vector<int>& chain = robot_.chains[static_cast<std::size_t>(sole.link)];
      const LinkJacobian& L = link_jacobian(sole.link, derivatives);
      double value = 0;
      Vec3 point = Vec3::Zero();
      int axis = 2;
      bool normal = false;
      if (rs.kind < 3) {
        point = X * sole.p_L_center;
        axis = rs.kind;
        value = point[axis];
        if (rs.kind < 2) {
          const int phase = pt.stance[static_cast<std::size_t>(rs.foot)];
          const double anchor = rs.anchor_var >= 0 ? 0.0 : spec_.anchors[static_cast<std::size_t>(phase)].p_W[rs.kind];
          value -= anchor;  // a variable anchor is subtracted below from x
        }
      } else if (rs.kind < kStanceRows) {
        normal = true;
        axis = rs.kind - 3;
        value = (X.linear() * robot_.n_L_sole[static_cast<std::size_t>(rs.foot)])[axis];
      } else {
        point = X * sole.corners_L()[static_cast<std::size_t>(rs.kind - kStanceRows)];
        value = point.z();
      }
      g_[pr.first_row + static_cast<int>(k)] = value;  // anchor variables are subtracted in evaluate()
      if (!derivatives) continue;
      const Vec3 n = X.linear() * robot_.n_L_sole[static_cast<std::size_t>(rs.foot)];
      const Vec3 op = point - L.p_W_origin;
      for (int d : chain) {
        const Vec3 w(L.jr(0, d), L.jr(1, d), L.jr(2, d));
        row[d] = normal ? w.cross(n)[axis] : (Vec3(L.jp(0, d), L.jp(1, d), L.jp(2, d)) - op.cross(w))[axis];
      }
      // Second derivatives over the chain (upper triangle): ω_i × ∂g/∂x_j for i up the chain from j;
      // the root tilt pair (a, b) adds the chart's own curvature (∂ω_j/∂x_i, root_omega_derivatives).
      {
        const Vec3 base = normal ? n : Vec3(point - xc_.head<3>());  // what the root rotation turns
        const int nc = static_cast<int>(chain.size());
        double* h2 = con_hess_.data() + rs.hess_offset;
        for (int b = 0; b < nc; ++b) {
          const int j = chain[static_cast<std::size_t>(b)];
          const Vec3 wj(L.jr(0, j), L.jr(1, j), L.jr(2, j));
          const Vec3 Dj = normal ? Vec3(wj.cross(n)) : Vec3(Vec3(L.jp(0, j), L.jp(1, j), L.jp(2, j)) - op.cross(wj));
          for (int a = 0; a <= b; ++a) {
            const int i = chain[static_cast<std::size_t>(a)];
            double v = 0;
            if (i >= 3) {
              const Vec3 wi(L.jr(0, i), L.jr(1, i), L.jr(2, i));
              if (i >= 4 && j <= 5)
                v = (dw_[static_cast<std::size_t>((i - 4) * 2 + (j - 4))].cross(base) + wj.cross(wi.cross(base)))[axis];
              else
                v = wi.cross(Dj)[axis];
            }
            h2[b * (b + 1) / 2 + a] = v;
          }
        }
      }
      int off = rs.value_offset;
      for (int a = 0; a < pt.support.count; ++a) {
        const int la = pt.support.index[static_cast<std::size_t>(a)] - spec_.first_control;
        if (!is_free(la)) continue;
        const double wa = pt.support.weight[static_cast<std::size_t>(a)];
        for (int d : chain) jac_[off++] = wa * row[d];
      }
      if (rs.anchor_var >= 0) jac_[off++] = -1.0;
    }
  }
  return cost;
}

void WindowNlp::lagrangian_hessian(double obj_factor, const double* lambda, double* values) {
  for (Eigen::Index e = 0; e < hess_.size(); ++e) values[e] = obj_factor * hess_[e];
  for (std::size_t p = 0; p < point_rows_.size(); ++p) {
    const PointRows& pr = point_rows_[p];
    if (pr.rows.empty()) continue;
    // All rows of a point share the sole link's chain: sum Σ λ ∇²g on the compact chain block.
    const std::vector<int>& chain = robot_.chains[static_cast<std::size_t>(pr.rows.front().chain_link)];
    const int nc = static_cast<int>(chain.size());
    MatX& B = chain_block_;
    B.setZero(nc, nc);
    bool any = false;
    for (std::size_t k = 0; k < pr.rows.size(); ++k) {
      const double l = lambda[pr.first_row + static_cast<int>(k)];
      if (l == 0) continue;
      any = true;
      const double* h2 = con_hess_.data() + pr.rows[k].hess_offset;
      for (int b = 0; b < nc; ++b)
        for (int a = 0; a <= b; ++a) B(a, b) += l * h2[b * (b + 1) / 2 + a];
    }
    if (!any) continue;
    B.triangularView<Eigen::StrictlyLower>() = B.transpose();
    if (convexify_) {
      // Keep the positive curvature only: the Gauss–Newton objective plus a positive semidefinite
      // constraint part never needs Ipopt's inertia correction, and the directions whose true
      // curvature is larger than Gauss–Newton's (the cause of drifting steps) are damped.
      eigen_.compute(B);
      B = eigen_.eigenvectors() * eigen_.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen_.eigenvectors().transpose();
    }
    Hc_.setZero();
    for (int b = 0; b < nc; ++b)
      for (int a = 0; a < nc; ++a) Hc_(chain[static_cast<std::size_t>(a)], chain[static_cast<std::size_t>(b)]) = B(a, b);
    scatter_point_block(spec_.points[p], values);
  }
}

void WindowNlp::evaluate(const double* x) {
  set_controls(x);
  f_ = 0;
  grad_.setZero();
  hess_.setZero();
  // Acceleration: √w (C_{j−1} − 2C_j + C_{j+1}) / h², per interior control point touching a free one.
  const double h2 = spec_.segment_s * spec_.segment_s;
  const double c[3] = {1.0 / h2, -2.0 / h2, 1.0 / h2};
  const double w = weights_.acceleration;
  for (int j = 1; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    const VecX a = (C_.col(j - 1) - 2.0 * C_.col(j) + C_.col(j + 1)) / h2;
    f_ += 0.5 * w * a.squaredNorm();
    for (int m = 0; m < 3; ++m) {
      const int lm = j - 1 + m;
      if (!is_free(lm)) continue;
      grad_.segment(var(lm, 0), nv_) += w * c[m] * a;
      for (int k = 0; k <= m; ++k) {
        const int lk = j - 1 + k;
        if (!is_free(lk)) continue;
        double* h = hess_.data() + block_offset(lm, lk);
        const std::vector<int>& diag = lm == lk ? diag_lower_ : diag_full_;
        for (int i = 0; i < nv_; ++i) h[diag[static_cast<std::size_t>(i)]] += w * c[m] * c[k];
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
  for (std::size_t p = 0; p < point_rows_.size(); ++p)
    for (std::size_t k = 0; k < point_rows_[p].rows.size(); ++k) {
      const RowSpan& rs = point_rows_[p].rows[k];
      if (rs.anchor_var >= 0) g_[point_rows_[p].first_row + static_cast<int>(k)] -= x[rs.anchor_var];
    }
}

VecX WindowNlp::residuals(const double* x) {
  set_controls(x);
  std::vector<double> r;
  const double h2 = spec_.segment_s * spec_.segment_s;
  const double sw = std::sqrt(weights_.acceleration);
  for (int j = 1; j + 1 < size_; ++j) {
    if (!is_free(j + 1)) continue;
    const VecX a = sw * (C_.col(j - 1) - 2.0 * C_.col(j) + C_.col(j + 1)) / h2;
    r.insert(r.end(), a.data(), a.data() + nv_);
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
