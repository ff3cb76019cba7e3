#include "src/refine/smooth_correction.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "retarget/model/centroidal.hpp"
#include "retarget/model/collision_hull.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt::refine {

namespace {

// One weighted residual row r + J δ, J over the `ncols` dofs at `cols` (indices into v; stable
// storage: a link's chain or the identity list), its entries at `jac` in the frame's buffer.
struct Row {
  double weight = 0;
  double residual = 0;
  double cost = -1;  ///< its share of the cost when not ½ w r² (the rows of a floor penalty)
  const int* cols = nullptr;
  std::size_t ncols = 0, jac = 0;
};

// The rows of one frame; cleared and refilled at every evaluation without allocating.
struct FrameRows {
  std::vector<Row> rows;
  std::vector<double> jac;
};

Vec3 rotation_log(const Mat3& R) {
  const AngleAxis aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

bool solve_block_pentadiagonal(std::vector<MatX>& D, std::vector<MatX>& E, std::vector<MatX>& F, std::vector<VecX>& b) {
  const std::size_t T = D.size();
  // Block Cholesky A = L Lᵀ in place, without allocating (this runs once per Gauss–Newton step on
  // thousands of frames): D[f] ← L(f, f) (lower triangle), E[f−1] ← L(f, f−1), F[f−2] ← L(f, f−2).
  for (std::size_t f = 0; f < T; ++f) {
    MatX& S = D[f];
    if (f >= 2) {
      D[f - 2].transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(F[f - 2]);
      S.selfadjointView<Eigen::Lower>().rankUpdate(F[f - 2], -1.0);
    }
    if (f >= 1) {
      if (f >= 2) E[f - 1].noalias() -= F[f - 2] * E[f - 2].transpose();
      D[f - 1].transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(E[f - 1]);
      S.selfadjointView<Eigen::Lower>().rankUpdate(E[f - 1], -1.0);
    }
    Eigen::LLT<Eigen::Ref<MatX>> llt(S);  // in place: S's lower triangle becomes L(f, f)
    if (llt.info() != Eigen::Success) return false;
  }
  for (std::size_t f = 0; f < T; ++f) {  // L y = b
    if (f >= 1) b[f].noalias() -= E[f - 1] * b[f - 1];
    if (f >= 2) b[f].noalias() -= F[f - 2] * b[f - 2];
    D[f].triangularView<Eigen::Lower>().solveInPlace(b[f]);
  }
  for (std::size_t f = T; f-- > 0;) {  // Lᵀ x = y
    if (f + 1 < T) b[f].noalias() -= E[f].transpose() * b[f + 1];
    if (f + 2 < T) b[f].noalias() -= F[f].transpose() * b[f + 2];
    D[f].triangularView<Eigen::Lower>().transpose().solveInPlace(b[f]);
  }
  return true;
}

VecX legs_first_stiffness(const RobotModel& model) {
  VecX stiffness = VecX::Constant(model.nv(), 30.0);
  stiffness.head<3>().setConstant(100.0);
  for (const Sole& sole : model.soles())
    for (int d : link_dof_chain(model, sole.link))
      if (d >= 6) stiffness[d] = 1.0;
  return stiffness;
}

MatX solve_smooth_correction(const RobotModel& model, RobotData& data, const MatX& q_base, const MatX& q_start,
                             const FootPlan& plan, const CorrectionOptions& o, CorrectionReport* report) {
  const int T = static_cast<int>(q_base.cols()), nv = model.nv();
  const mjModel* m = model.mj();
  MatX Delta(nv, T);
  for (int f = 0; f < T; ++f) Delta.col(f) = difference(model, q_base.col(f), q_start.col(f), 1.0);
  CorrectionReport rep;
  if (T == 0) return q_base;
  // A row counts as met within these (the refine bars are 1 mm and 0.5 deg per stance).
  constexpr double kStanceTolerance_m = 5e-4, kStanceTolerance_rad = 4e-3;
  constexpr double kLimitTolerance_rad = 1e-3;  // position limits, and speed limits per frame
  constexpr double kZmpTolerance_m = 1e-3;
  std::vector<std::vector<int>> chain_of(model.links().size());
  auto chain = [&](int link) -> const std::vector<int>& {
    auto& c = chain_of[static_cast<std::size_t>(link)];
    if (c.empty()) c = link_dof_chain(model, link);
    return c;
  };
  MatXr jp(3, nv), jr(3, nv);
  std::vector<FrameRows> rows(static_cast<std::size_t>(T));
  std::vector<int> dof_ids(static_cast<std::size_t>(nv));
  for (int d = 0; d < nv; ++d) dof_ids[static_cast<std::size_t>(d)] = d;
  const bool use_metric = o.metric.size() == static_cast<std::size_t>(T);
  std::vector<int> metric_index(static_cast<std::size_t>(nv), -1);
  for (std::size_t k = 0; k < o.metric_dofs.size(); ++k) metric_index[static_cast<std::size_t>(o.metric_dofs[k])] = static_cast<int>(k);
  // σ: each coordinate's typical (median) diagonal of M + ρ.
  VecX sigma = o.stiffness;
  if (use_metric)
    for (std::size_t k = 0; k < o.metric_dofs.size(); ++k) {
      std::vector<double> d;
      for (const MatX& M : o.metric) d.push_back(M(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
      std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
      sigma[o.metric_dofs[k]] += d[d.size() / 2];
    }
  // Δ restricted to the metric coordinates at frame f.
  auto metric_part = [&](const MatX& D, int f) {
    VecX x(static_cast<Eigen::Index>(o.metric_dofs.size()));
    for (std::size_t k = 0; k < o.metric_dofs.size(); ++k) x[static_cast<Eigen::Index>(k)] = D(o.metric_dofs[k], f);
    return x;
  };
  std::vector<FloorPenalty> penalties;
  VecX q(model.nq());

  // Rows at Δ = D, the coordinates they move, and the cost (the header's objective).
  struct SpeedRow {
    int frame, dof;    // frames frame and frame + 1, velocity coordinate dof (a joint)
    double residual;   // [rad per frame] beyond the limit
  };
  // A violated ZMP half-plane at `frame`: n, the residual nᵀp − d [m], and the terms the Jacobian
  // holds fixed; at_rest: a rested end's row on its COM (p = c).
  struct ZmpRow {
    int frame;
    Vec2 n;
    double residual, com_height_m, vertical_force;  // c_z [m], g + c̈_z [m/s²]
    bool at_rest = false;
    bool vertical = false;  // the support row on c̈_z (n unused): residual (c_z / g)((ε − 1) g − c̈_z)
  };
  const bool zmp_on = o.zmp_support.size() == static_cast<std::size_t>(T) && o.zmp_weight > 0 && o.fps > 0 && T >= 3;
  const double mass = m->body_subtreemass[model.root_body()];
  MatX q_all(model.nq(), zmp_on ? T : 0);
  Mat3X com_all(3, zmp_on ? T : 0), L_half(3, zmp_on ? T - 1 : 0);  // L_half.col(f): between f and f + 1
  MatX A_L_prev;
  // miss_out: the largest miss of a row the correction must meet (stance soles, limits, speed
  // limits, ZMP) in multiples of its tolerance: <= 1 when all are met.
  auto evaluate = [&](const MatX& D, std::vector<FrameRows>& rows_out, std::vector<std::uint8_t>& used,
                      std::vector<SpeedRow>& speed_out, std::vector<ZmpRow>& zmp_out, double& miss_out) {
    speed_out.clear();
    zmp_out.clear();
    miss_out = 0;
    ++rep.evaluations;
    used.assign(static_cast<std::size_t>(nv), 0);
    for (int foot = 0; foot < 2; ++foot)
      for (int d : chain(model.soles()[static_cast<std::size_t>(foot)].link)) used[static_cast<std::size_t>(d)] = 1;
    if (zmp_on)
      for (int f = 0; f < T; ++f) q_all.col(f) = integrate(model, q_base.col(f), D.col(f), 1.0);
    for (int f = 0; f < T; ++f) {
      auto& fr = rows_out[static_cast<std::size_t>(f)];
      fr.rows.clear();
      fr.jac.clear();
      q = zmp_on ? VecX(q_all.col(f)) : integrate(model, q_base.col(f), D.col(f), 1.0);
      update_kinematics(model, data, q);
      if (zmp_on) {
        // The multibody ZMP's momenta exactly as multibody_zmp computes them (L at the half-frames).
        com_all.col(f) = com_position(model, data);
        MatX A_L = centroidal_angular_matrix(model, data);
        if (f > 0) L_half.col(f - 1) = half_frame_angular_momentum(model, A_L_prev, A_L, q_all.col(f - 1), q_all.col(f), 1.0 / o.fps);
        A_L_prev = std::move(A_L);
      }
      std::array<int, 2> skip{{-1, -1}};
      std::vector<std::pair<int, double>> min_height;
      for (int foot = 0; foot < 2; ++foot) {
        const auto k = static_cast<std::size_t>(foot);
        const FootTarget& t = plan.feet[k][static_cast<std::size_t>(f)];
        const Sole& sole = model.soles()[k];
        if (t.mode == FootMode::Stance) skip[k] = sole.link;
        else min_height.emplace_back(sole.link, t.min_height_m);
        if (t.mode == FootMode::Free) continue;
        const double blend = t.mode == FootMode::Stance ? 1.0 : t.end_blend;
        const double w = o.swing_weight + (o.stance_weight - o.swing_weight) * blend;
        const double len = o.swing_length_m + (o.stance_length_m - o.swing_length_m) * blend;
        const Iso3 X = link_pose(model, data, sole.link);
        const Vec3 p = X * sole.p_L_center;
        const Vec3 e_p = p - t.pose.p_W;
        const Vec3 e_o = rotation_log(X.linear() * o.R_L_sole[k] * t.pose.R_W.transpose());
        if (t.mode == FootMode::Stance)
          miss_out = std::max({miss_out, e_p.norm() / kStanceTolerance_m, e_o.norm() / kStanceTolerance_rad});
        mj_jac(m, data.mj(), jp.data(), jr.data(), p.data(), model.links()[static_cast<std::size_t>(sole.link)].body);
        const std::vector<int>& cols = chain(sole.link);
        for (int r = 0; r < 6; ++r) {
          Row row;
          row.weight = r < 3 ? w : w * len * len;
          row.residual = r < 3 ? e_p[r] : e_o[r - 3];
          row.cols = cols.data();
          row.ncols = cols.size();
          row.jac = fr.jac.size();
          for (int c : cols) fr.jac.push_back(r < 3 ? jp(r, c) : jr(r - 3, c));
          fr.rows.push_back(row);
        }
      }
      for (int i = 0; i < model.nu(); ++i) {
        const double v = q[7 + i];
        const double excess = v > o.q_upper[i] ? v - o.q_upper[i] : (v < o.q_lower[i] ? v - o.q_lower[i] : 0.0);
        if (excess == 0) continue;
        miss_out = std::max(miss_out, std::abs(excess) / kLimitTolerance_rad);
        Row row;
        row.weight = o.limit_weight;
        row.residual = excess;
        row.cols = &dof_ids[static_cast<std::size_t>(6 + i)];
        row.ncols = 1;
        row.jac = fr.jac.size();
        fr.jac.push_back(1.0);
        used[static_cast<std::size_t>(6 + i)] = 1;
        fr.rows.push_back(row);
      }
      penalties.clear();
      floor_penalties(model, data, o.floor_weight, min_height, skip, penalties);
      for (const FloorPenalty& pen : penalties) {
        // Three rows R = Lᵀ B with residuals L⁻¹ m (M = L Lᵀ) give the same normal equations.
        mj_jac(m, data.mj(), jp.data(), jr.data(), pen.p_W_origin.data(), model.links()[static_cast<std::size_t>(pen.link)].body);
        const Eigen::LLT<Mat3> llt(pen.M + 1e-12 * Mat3::Identity());
        const Mat3 L = llt.matrixL();
        const Vec3 res = L.triangularView<Eigen::Lower>().solve(pen.m);
        const std::vector<int>& cols = chain(pen.link);
        for (int r = 0; r < 3; ++r) {
          Row row;
          row.weight = 1;
          row.residual = res[r];
          row.cols = cols.data();
          row.ncols = cols.size();
          row.jac = fr.jac.size();
          for (int c : cols) {
            const Vec3 bc(jp(2, c), jr(0, c), jr(1, c));
            fr.jac.push_back(L.col(r).dot(bc));
            used[static_cast<std::size_t>(c)] = 1;
          }
          row.cost = r == 0 ? pen.cost : 0.0;
          fr.rows.push_back(row);
        }
      }
    }
    if (o.max_step.size() == model.nu())
      for (int f = 0; f + 1 < T; ++f)
        for (int i = 0; i < model.nu(); ++i) {
          const double lim = o.max_step[i];
          if (!(lim > 0)) continue;
          const double step = q_base(7 + i, f + 1) + D(6 + i, f + 1) - q_base(7 + i, f) - D(6 + i, f);
          if (std::abs(step) <= lim) continue;
          speed_out.push_back({f, 6 + i, step - std::copysign(lim, step)});
          miss_out = std::max(miss_out, std::abs(speed_out.back().residual) / kLimitTolerance_rad);
          used[static_cast<std::size_t>(6 + i)] = 1;
        }
    if (zmp_on) {
      // The multibody ZMP exactly as multibody_zmp computes it.
      for (int f = 1; f + 1 < T; ++f) {
        const std::vector<HalfPlane>& support = o.zmp_support[static_cast<std::size_t>(f)];
        if (support.empty()) continue;
        const ZmpSample z = zmp_sample(com_all.col(f - 1), com_all.col(f), com_all.col(f + 1), L_half.col(f - 1), L_half.col(f), mass, o.fps);
        for (const HalfPlane& hp : support) {
          const double r = hp.n.dot(z.zmp_W) - hp.d;
          if (r > 0) zmp_out.push_back({f, hp.n, r, com_all(2, f), z.vertical_accel});
        }
        const double support_shortfall = o.zmp_min_support_g * kGravity - z.vertical_accel_raw;  // [m/s²]
        if (support_shortfall > 0)
          zmp_out.push_back({f, Vec2::Zero(), com_all(2, f) / kGravity * support_shortfall, com_all(2, f), z.vertical_accel, false, true});
      }
      for (const int f : {0, T - 1}) {
        if (!(f == 0 ? o.zmp_rest_start : o.zmp_rest_end)) continue;
        for (const HalfPlane& hp : o.zmp_support[static_cast<std::size_t>(f)]) {
          const double r = hp.n.dot(com_all.col(f).head<2>()) - hp.d;
          if (r > 0) zmp_out.push_back({f, hp.n, r, com_all(2, f), kGravity, true});
        }
      }
      if (!zmp_out.empty()) used.assign(static_cast<std::size_t>(nv), 1);
      for (const ZmpRow& r : zmp_out) miss_out = std::max(miss_out, r.residual / kZmpTolerance_m);
    }
    double cost = 0;
    for (const ZmpRow& r : zmp_out) cost += 0.5 * o.zmp_weight * r.residual * r.residual;
    for (const SpeedRow& r : speed_out) cost += 0.5 * o.limit_weight * r.residual * r.residual;
    for (const auto& fr : rows_out)
      for (const Row& row : fr.rows) cost += row.cost >= 0 ? row.cost : 0.5 * row.weight * row.residual * row.residual;
    for (int f = 0; f < T; ++f) {
      cost += 0.5 * D.col(f).dot(o.stiffness.cwiseProduct(D.col(f)));
      if (use_metric) {
        const VecX x = metric_part(D, f);
        cost += 0.5 * x.dot(o.metric[static_cast<std::size_t>(f)] * x);
      }
      if (o.lambda > 0 && f >= 1 && f + 1 < T) {
        const VecX d2 = D.col(f - 1) - 2 * D.col(f) + D.col(f + 1);
        cost += 0.5 * o.lambda * d2.dot(sigma.cwiseProduct(d2));
      }
    }
    return cost;
  };
  std::vector<std::uint8_t> used, used_try;
  std::vector<FrameRows> rows_try(static_cast<std::size_t>(T));
  std::vector<SpeedRow> speed, speed_try;
  std::vector<ZmpRow> zmp, zmp_try;
  double miss = 0, miss_try = 0;
  double cost = evaluate(Delta, rows, used, speed, zmp, miss);
  std::vector<MatX> Dblk, Eblk, Fblk;  // the normal equations' blocks (see solve_block_pentadiagonal)
  std::vector<VecX> b;
  constexpr int kDampedAttempts = 3;      // damped solves after a rejected Gauss–Newton step
  constexpr double kFirstDamping = 1e-2;  // μ of the first, ×10 for each further one
  for (int it = 0; it < o.iterations + o.extra_iterations; ++it) {
    if (it >= o.iterations && miss <= 1) break;  // the extra steps only while a row is missed
    std::vector<int> vars, index(static_cast<std::size_t>(nv), -1);
    for (int d = 0; d < nv; ++d)
      if (used[static_cast<std::size_t>(d)]) {
        index[static_cast<std::size_t>(d)] = static_cast<int>(vars.size());
        vars.push_back(d);
      }
    const auto n = static_cast<Eigen::Index>(vars.size());
    VecX rho(n), sig(n);
    for (Eigen::Index a = 0; a < n; ++a) {
      rho[a] = o.stiffness[vars[static_cast<std::size_t>(a)]];
      sig[a] = sigma[vars[static_cast<std::size_t>(a)]];
    }

    // Assembles the normal equations at Δ into Dblk, Eblk, Fblk, b (again for a damped retry:
    // the solve factorises them in place).
    auto assemble = [&] {
      // Normal equations: H = Σ w JᵀJ + ρ + λ ρ DᵀD, g = Σ w Jᵀ r + ρ Δ + λ ρ DᵀD Δ.
      // The blocks' storage is reused across iterations (tens of MB on a long clip).
      auto zero_blocks = [n](std::vector<MatX>& blocks, int count) {
        blocks.resize(static_cast<std::size_t>(std::max(0, count)));
        for (MatX& B : blocks) B.setZero(n, n);
      };
      zero_blocks(Dblk, T);
      zero_blocks(Eblk, T - 1);
      zero_blocks(Fblk, T - 2);
      b.resize(static_cast<std::size_t>(T));
      for (VecX& v : b) v.setZero(n);
      auto dd = [&](int f, int g) {  // (DᵀD)(f, g) of the second-difference operator over T frames
        double s = 0;
        for (int k = std::max(1, std::max(f, g) - 1); k <= std::min(T - 2, std::min(f, g) + 1); ++k) {
          const auto coeff = [&](int x) { return x == k ? -2.0 : (std::abs(x - k) == 1 ? 1.0 : 0.0); };
          s += coeff(f) * coeff(g);
        }
        return s;
      };
      VecX Df(n);
      for (int f = 0; f < T; ++f) {
        MatX& H = Dblk[static_cast<std::size_t>(f)];
        VecX& g = b[static_cast<std::size_t>(f)];
        const FrameRows& fr = rows[static_cast<std::size_t>(f)];
        for (const Row& row : fr.rows) {
          const double* jac = fr.jac.data() + row.jac;
          for (std::size_t a = 0; a < row.ncols; ++a) {
            const int ia = index[static_cast<std::size_t>(row.cols[a])];
            g[ia] += row.weight * jac[a] * row.residual;
            for (std::size_t c = 0; c < row.ncols; ++c)
              H(ia, index[static_cast<std::size_t>(row.cols[c])]) += row.weight * jac[a] * jac[c];
          }
        }
        for (Eigen::Index a = 0; a < n; ++a) Df[a] = Delta(vars[static_cast<std::size_t>(a)], f);
        H.diagonal() += rho;
        g += rho.cwiseProduct(Df);
        if (use_metric) {
          const MatX& M = o.metric[static_cast<std::size_t>(f)];
          const VecX Mx = M * metric_part(Delta, f);
          for (Eigen::Index a = 0; a < n; ++a) {
            const int ka = metric_index[static_cast<std::size_t>(vars[static_cast<std::size_t>(a)])];
            if (ka < 0) continue;
            g[a] += Mx[ka];
            for (Eigen::Index c = 0; c < n; ++c) {
              const int kc = metric_index[static_cast<std::size_t>(vars[static_cast<std::size_t>(c)])];
              if (kc >= 0) H(a, c) += M(ka, kc);
            }
          }
        }
        if (o.lambda > 0) {
          H.diagonal() += o.lambda * dd(f, f) * sig;
          VecX smooth = VecX::Zero(n);
          for (int h = std::max(0, f - 2); h <= std::min(T - 1, f + 2); ++h) {
            const double c = dd(f, h);
            if (c == 0) continue;
            for (Eigen::Index a = 0; a < n; ++a) smooth[a] += c * Delta(vars[static_cast<std::size_t>(a)], h);
          }
          g += o.lambda * sig.cwiseProduct(smooth);
        }
        g = -g;
      }
      if (o.lambda > 0) {
        for (int f = 0; f + 1 < T; ++f) Eblk[static_cast<std::size_t>(f)].diagonal() = o.lambda * dd(f + 1, f) * sig;
        for (int f = 0; f + 2 < T; ++f) Fblk[static_cast<std::size_t>(f)].diagonal() = o.lambda * dd(f + 2, f) * sig;
      }
      // Speed rows: residual r = (Δ_f+1 − Δ_f) + ... beyond the limit, Jacobian (−1, +1).
      for (const SpeedRow& r : speed) {
        const int a = index[static_cast<std::size_t>(r.dof)];
        const auto f = static_cast<std::size_t>(r.frame);
        Dblk[f](a, a) += o.limit_weight;
        Dblk[f + 1](a, a) += o.limit_weight;
        Eblk[f](a, a) -= o.limit_weight;
        b[f][a] += o.limit_weight * r.residual;
        b[f + 1][a] -= o.limit_weight * r.residual;
      }
      // ZMP rows: Jacobian blocks G_k over all coordinates for k = f − 1, f, f + 1 (see the header);
      // every coordinate is a variable once a ZMP row exists, so vars is the identity then.
      if (!zmp.empty()) {
        std::vector<MatX> J_com(static_cast<std::size_t>(T)), A_L(static_cast<std::size_t>(T));
        std::vector<VecX> Jz_com(static_cast<std::size_t>(T));
        auto jacobians_at = [&](int k) {
          if (J_com[static_cast<std::size_t>(k)].size() > 0) return;
          update_kinematics(model, data, integrate(model, q_base.col(k), Delta.col(k), 1.0));
          const MatX J = com_jacobian(model, data);
          J_com[static_cast<std::size_t>(k)] = J.topRows<2>();
          Jz_com[static_cast<std::size_t>(k)] = J.row(2).transpose();
          A_L[static_cast<std::size_t>(k)] = centroidal_angular_matrix(model, data).topRows<2>();
        };
        const double f2 = o.fps * o.fps;
        std::array<VecX, 3> G;
        for (const ZmpRow& z : zmp) {
          const int f = z.frame;
          if (z.at_rest) {
            jacobians_at(f);
            const VecX nJ = J_com[static_cast<std::size_t>(f)].transpose() * z.n;
            b[static_cast<std::size_t>(f)].noalias() -= o.zmp_weight * z.residual * nJ;
            Dblk[static_cast<std::size_t>(f)].noalias() += o.zmp_weight * nJ * nJ.transpose();
            continue;
          }
          for (int k = f - 1; k <= f + 1; ++k) jacobians_at(k);
          if (z.vertical) {  // residual (c_z / g)(const − c̈_z): G_k = −(c_z / g) fps² J_z,k (1, −2, 1)
            const double s = z.com_height_m / kGravity * f2;
            for (int k = 0; k < 3; ++k)
              G[static_cast<std::size_t>(k)] = (k == 1 ? 2 * s : -s) * Jz_com[static_cast<std::size_t>(f - 1 + k)];
          } else {
          const double a = z.com_height_m / z.vertical_force * f2, l = f2 / (mass * z.vertical_force);
          const Vec2 s_n(-z.n.y(), z.n.x());  // nᵀ S, S L̇ = (L̇_y, −L̇_x)
          const VecX sA = A_L[static_cast<std::size_t>(f)].transpose() * s_n;
          for (int k = 0; k < 3; ++k) {
            const VecX nJ = J_com[static_cast<std::size_t>(f - 1 + k)].transpose() * z.n;
            G[static_cast<std::size_t>(k)] = k == 1 ? VecX((1 + 2 * a) * nJ + 2 * l * sA) : VecX(-a * nJ - l * sA);
          }
          }
          const double w = o.zmp_weight;
          for (int k1 = 0; k1 < 3; ++k1) {
            const auto fk1 = static_cast<std::size_t>(f - 1 + k1);
            b[fk1].noalias() -= w * z.residual * G[static_cast<std::size_t>(k1)];
            for (int k2 = 0; k2 <= k1; ++k2) {
              const auto fk2 = static_cast<std::size_t>(f - 1 + k2);
              MatX& block = k1 == k2 ? Dblk[fk1] : (k1 == k2 + 1 ? Eblk[fk2] : Fblk[fk2]);
              block.noalias() += w * G[static_cast<std::size_t>(k1)] * G[static_cast<std::size_t>(k2)].transpose();
            }
          }
        }
      }
    };
    assemble();
    // Backtracking on the cost: the one-sided rows change their active set between steps. Where no
    // step along the Gauss–Newton direction lowers the cost while a row is still missed (the
    // linearised rows of a leg at its limits, its speed limits and two stance soles disagree), the
    // step is damped (Levenberg–Marquardt, H + μ diag H) and tried again rather than the solve
    // stopping there.
    double alpha = 1, step = 0;
    bool accepted = false;
    MatX Delta_try = Delta;
    const double cost_before = cost;
    for (int attempt = 0; attempt <= (miss > 1 && o.extra_iterations > 0 ? kDampedAttempts : 0) && !accepted; ++attempt) {
      if (attempt > 0) {
        assemble();
        const double mu = kFirstDamping * std::pow(10.0, attempt - 1);
        for (MatX& H : Dblk) H.diagonal() *= 1 + mu;
      }
      if (!solve_block_pentadiagonal(Dblk, Eblk, Fblk, b)) break;
      alpha = 1;
      for (int k = 0; k < (attempt == 0 ? 5 : 2) && !accepted; ++k, alpha *= 0.5) {
        step = 0;
        for (int f = 0; f < T; ++f)
          for (Eigen::Index a = 0; a < n; ++a) {
            const double d = alpha * b[static_cast<std::size_t>(f)][a];
            Delta_try(vars[static_cast<std::size_t>(a)], f) = Delta(vars[static_cast<std::size_t>(a)], f) + d;
            step = std::max(step, std::abs(d));
          }
        const double cost_try = evaluate(Delta_try, rows_try, used_try, speed_try, zmp_try, miss_try);
        if (cost_try < cost) {
          accepted = true;
          cost = cost_try;
          Delta.swap(Delta_try);
          rows.swap(rows_try);
          used.swap(used_try);
          speed.swap(speed_try);
          zmp.swap(zmp_try);
          miss = miss_try;
        }
      }
    }
    rep.iterations = it + 1;
    rep.coordinates = static_cast<int>(n);
    rep.max_step = step;
    // Stop when the step is negligible or the cost no longer falls by 1e-6 of itself.
    if (!accepted || step < 1e-6 || cost_before - cost < 1e-6 * cost_before) break;
  }
  MatX out(model.nq(), T);
  for (int f = 0; f < T; ++f) out.col(f) = integrate(model, q_base.col(f), Delta.col(f), 1.0);
  rep.zmp_rows = static_cast<int>(zmp.size());
  for (const ZmpRow& z : zmp) rep.zmp_excess_max = std::max(rep.zmp_excess_max, z.residual);
  if (report) *report = rep;
  return out;
}

}  // namespace rt::refine
