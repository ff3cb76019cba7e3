#include "retarget/passes/refine_ipopt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/ik/landmark_ik.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/ground.hpp"
#include "retarget/passes/ik_pass.hpp"
#include "retarget/passes/quality.hpp"
#include "src/refine/bspline.hpp"
#include "src/refine/ipopt_solver.hpp"
#include "src/refine/trajectory_chart.hpp"
#include "src/refine/window_nlp.hpp"

namespace rt {

namespace {

using refine::CollocationPoint;
using refine::NlpRobot;
using refine::StanceAnchor;
using refine::WindowSpec;

// A labelled stance phase of one foot: source frames [begin, end).
struct Phase {
  int foot = 0;
  int begin = 0, end = 0;
  bool anchor_known = false;  // solved by an earlier window
  Vec2 anchor = Vec2::Zero();
};

// Frames x joints whose finite-difference velocity exceeds the URDF limit (quality.hpp's definition).
int velocity_violations(const RobotModel& model, const MatX& q, double fps) {
  int n = 0;
  for (Eigen::Index f = 1; f < q.cols(); ++f)
    for (int i = 0; i < model.nu(); ++i) {
      const double limit = model.velocity_limits()[i];
      if (limit > 0 && std::abs(q(7 + i, f) - q(7 + i, f - 1)) * fps > limit) ++n;
    }
  return n;
}

VecX config_at(const MatX& controls, double t, int nq) {
  VecX q(nq);
  refine::q_from_chart(refine::spline_value(controls, t), q);
  return q;
}

}  // namespace

RefineIpoptPass::RefineIpoptPass() {
  table_.add("knot_fps", options_.knot_fps, "[Hz] spline knot rate (stride = round(source fps / knot_fps))",
             {0.1, 1000, "Hz"});
  table_.add("window", options_.window, "spline control points per window", {4, 10000, ""});
  table_.add("overlap", options_.overlap, "control points shared by consecutive windows (>= 3)", {3, 10000, ""});
  table_.add("acceleration_weight", options_.acceleration_weight, "weight of the squared acceleration per control point");
  table_.add("pull_weight", options_.pull_weight, "weight of the squared distance to the per-frame IK");
  table_.add("interpolated_weight", options_.interpolated_weight, "weight factor of gap-filled landmark samples");
  table_.add("stance_weight", options_.stance_weight, "weight factor of foot landmarks in stance");
  table_.add("velocity_margin", options_.velocity_margin, "fraction of each velocity limit kept free");
  table_.add("velocity_activation", options_.velocity_activation, "velocity rows enter the NLP above this fraction of their bound");
  table_.add("limit_margin", options_.limit_margin, "[rad, m] distance kept from the joint position limits");
  table_.add("floor_check_height", options_.floor_check_height, "[m] swing-foot corners below this are kept above the floor");
  table_.add("max_iterations", options_.max_iterations, "Ipopt iterations per window", {1, 100000, ""});
  table_.add("tolerance", options_.tolerance, "Ipopt convergence tolerance");
  table_.add("mu_init", options_.mu_init, "Ipopt initial barrier parameter");
}

void RefineIpoptPass::run(Clip& clip, PassContext& ctx) {
  const RobotModel& model = ctx.model();
  RobotData& data = ctx.data();
  RobotMotion& motion = clip.motion;
  const RefineIpoptOptions& o = options_;
  const int T = motion.num_frames();
  const std::string where = clip.human.source.path.empty() ? clip.name : clip.human.source.path;
  if (T == 0) throw InputError("--passes", "refine-ipopt needs the robot motion of the ik pass: put ik before it");
  if (!clip.targets[Landmark::Pelvis].present) throw InputError("--passes", "refine-ipopt needs the scale pass before it");
  require_input(o.knot_fps > 0 && o.window >= 5 && o.overlap >= 3 && o.overlap < o.window, "refine-ipopt",
                "options need knot_fps > 0, window >= 5 and 3 <= overlap < window");
  require_input(o.acceleration_weight >= 0 && o.pull_weight >= 0 && o.velocity_margin >= 0.001 && o.velocity_margin < 1 &&
                    o.velocity_activation >= 0 && o.limit_margin >= 0 && o.interpolated_weight >= 0 && o.stance_weight >= 0,
                "refine-ipopt", "weights and margins must be >= 0, velocity_margin in [0.001, 1)");
  require_input(o.max_iterations >= 1 && o.tolerance > 0 && o.mu_init > 0, "refine-ipopt",
                "max_iterations must be >= 1, tolerance and mu_init > 0");
  if (T < 4 || !(motion.fps > 0)) {
    ctx.statistics.set("skipped", 1, "", "fewer than 4 frames");
    return;
  }
  const auto t_start = std::chrono::steady_clock::now();
  const double fps = motion.fps;
  const int nq = model.nq(), nv = model.nv();

  // ---- vertical alignment ----
  // The per-frame IK leaves stance feet wherever the scaled landmarks put them, often centimetres
  // above or below the floor; the ground pass (after refine) moves the whole robot vertically to fix
  // that. The NLP holds stance soles on the floor, so it sees that vertical offset first: the IK
  // trajectory and the landmark targets are shifted by the ground pass's own per-frame offset, and
  // landmark costs do not fight the floor constraints (which would straighten the knees).
  VecX dz_ground = VecX::Zero(T);
  {
    Clip grounded;
    grounded.motion = motion;
    grounded.contacts = clip.contacts;
    Statistics statistics;
    Diagnostics diagnostics;
    PassContext ground_ctx{&model, &data, statistics, diagnostics};
    GroundPass().run(grounded, ground_ctx);
    dz_ground = (grounded.motion.q.row(2) - motion.q.row(2)).transpose();
  }
  MatX q_in = motion.q;
  q_in.row(2) += dz_ground.transpose();

  // ---- chart trajectory of the per-frame IK (yaw unwrapped along the clip) ----
  MatX X_ik(nv, T);
  double yaw = 0, max_tilt = 0;
  int worst_tilt_frame = 0;
  for (int f = 0; f < T; ++f) {
    const Quat R(motion.q(3, f), motion.q(4, f), motion.q(5, f), motion.q(6, f));
    if (f == 0) yaw = refine::root_yaw(R.normalized(), 0.0);
    X_ik.col(f) = refine::chart_from_q(q_in.col(f), yaw);
    yaw = X_ik(3, f);
    const double tilt = refine::tilt_angle(R);
    if (tilt > max_tilt) {
      max_tilt = tilt;
      worst_tilt_frame = f;
    }
  }
  if (max_tilt > 0.8 * M_PI) {
    ctx.diagnostics.warn(where + " frame " + std::to_string(worst_tilt_frame),
                         format("refine-ipopt: skipped, the root is upside down (tilt %.0f deg) where the spline chart is singular",
                                max_tilt * 180 / M_PI));
    ctx.statistics.set("skipped", 1, "", "root upside down");
    return;
  }

  const NlpRobot robot(model, o.limit_margin);
  const int stride = std::max(1, static_cast<int>(std::lround(fps / o.knot_fps)));
  const int N = refine::spline_num_controls(T, stride);
  MatX C = refine::spline_fit(X_ik, stride);
  for (int j = 0; j < N; ++j)
    for (int i = 6; i < nv; ++i) C(i, j) = std::clamp(C(i, j), robot.lower[i], robot.upper[i]);

  const double jitter_before = joint_jitter(motion.q, fps);
  const int velocity_before = velocity_violations(model, motion.q, fps);

  // ---- stance phases ----
  LandmarkTargets targets = clip.targets;
  for (LandmarkTrack& track : targets.tracks)
    if (track.present) track.p_W.row(2) += dz_ground.transpose();
  const bool have_contacts = !clip.contacts.empty();
  if (have_contacts) lock_stance_feet(model, targets, clip.contacts);
  std::vector<Phase> phases;
  std::array<std::vector<int>, 2> phase_of;
  for (int foot = 0; foot < 2; ++foot) {
    phase_of[static_cast<std::size_t>(foot)].assign(static_cast<std::size_t>(T), -1);
    if (!have_contacts) continue;
    const auto& c = clip.contacts.in_contact[static_cast<std::size_t>(foot)];
    for (int f = 0; f < T;) {
      if (!c[static_cast<std::size_t>(f)]) {
        ++f;
        continue;
      }
      Phase ph;
      ph.foot = foot;
      ph.begin = f;
      while (f < T && c[static_cast<std::size_t>(f)]) phase_of[static_cast<std::size_t>(foot)][static_cast<std::size_t>(f++)] = static_cast<int>(phases.size());
      ph.end = f;
      phases.push_back(ph);
    }
  }

  // ---- collocation points: every knot frame and the last frame ----
  const LandmarkIk ik(model);
  std::vector<CollocationPoint> points;
  // Stance boundaries are collocated too, so that a foot is at its anchor from the first frame of
  // its stance phase (foot skating is measured from there), not only from the next knot, and lands
  // and lifts off at rest (still rows). A knot closer than a stride to such a frame (or to the last
  // frame) is not collocated: collocation frames closer than a spline segment repeat nearly the same
  // constraint rows and make the KKT systems ill-conditioned (measured with half a stride: Ipopt
  // stalled on a third of the windows). Boundaries of the two feet are all kept, however close:
  // dropping one cost several millimetres of skating and no measured clip stalled on them.
  std::vector<int> frames, fixed_frames{T - 1};
  for (const Phase& ph : phases) {
    fixed_frames.push_back(ph.begin);
    fixed_frames.push_back(ph.end - 1);
  }
  std::sort(fixed_frames.begin(), fixed_frames.end());
  fixed_frames.erase(std::unique(fixed_frames.begin(), fixed_frames.end()), fixed_frames.end());
  const int min_gap = stride;
  for (int f = 0; f < T; f += stride) {
    const auto it = std::lower_bound(fixed_frames.begin(), fixed_frames.end(), f - min_gap + 1);
    if (it == fixed_frames.end() || *it >= f + min_gap) frames.push_back(f);
  }
  frames.insert(frames.end(), fixed_frames.begin(), fixed_frames.end());
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  int floor_rows = 0, stance_points = 0;
  for (int f : frames) {
    CollocationPoint p;
    p.frame = f;
    p.support = refine::spline_support(static_cast<double>(f) / stride, N);
    p.targets = make_ik_targets(model, ik, targets, f, o.interpolated_weight, nullptr, have_contacts ? &clip.contacts : nullptr,
                                have_contacts ? o.stance_weight : 1.0);
    p.x_ik = X_ik.col(f);
    update_kinematics(model, data, config_at(C, static_cast<double>(f) / stride, nq));
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      p.stance[k] = phase_of[k][static_cast<std::size_t>(f)];
      if (p.stance[k] >= 0) {
        ++stance_points;
        continue;
      }
      const Sole& sole = model.soles()[k];
      const Iso3 X = link_pose(model, data, sole.link);
      double lowest = INFINITY;
      for (const Vec3& c : sole.corners_L()) lowest = std::min(lowest, (X * c).z());
      p.floor[k] = lowest < o.floor_check_height;
      floor_rows += p.floor[k] ? 4 : 0;
    }
    points.push_back(std::move(p));
  }

  // A foot lands and lifts off at rest: zero sole velocity at each phase's first and last
  // collocation frame (its boundary frames unless merged above).
  for (std::size_t g = 0; g < phases.size(); ++g) {
    const auto k = static_cast<std::size_t>(phases[g].foot);
    CollocationPoint* first = nullptr;
    CollocationPoint* last = nullptr;
    for (CollocationPoint& p : points)
      if (p.stance[k] == static_cast<int>(g)) {
        if (!first) first = &p;
        last = &p;
      }
    if (first) first->still[k] = last->still[k] = true;
  }

  // ---- windows over the control points ----
  std::vector<std::pair<int, int>> windows;  // [first, last] control points
  if (N <= o.window) {
    windows.emplace_back(0, N - 1);
  } else {
    const int count = (N - o.overlap + (o.window - o.overlap) - 1) / (o.window - o.overlap);
    const double step = static_cast<double>(N - o.overlap) / count;
    for (int w = 0; w < count; ++w) {
      const int a = static_cast<int>(std::lround(w * step));
      const int b = w + 1 == count ? N - 1 : static_cast<int>(std::lround((w + 1) * step)) + o.overlap - 1;
      windows.emplace_back(a, b);
    }
  }

  refine::NlpWeights weights;
  weights.acceleration = o.acceleration_weight;
  weights.pull = o.pull_weight;
  weights.velocity_margin = o.velocity_margin;
  weights.velocity_activation = o.velocity_activation;
  refine::IpoptSettings settings;
  settings.max_iterations = o.max_iterations;
  settings.tolerance = o.tolerance;
  settings.mu_init = o.mu_init;

  // Two stages per window (see the header): the coordinates that move a foot, with the contact
  // constraints; then the others with those fixed.
  std::vector<std::uint8_t> feet_coordinates = robot.moves_feet, other_coordinates(static_cast<std::size_t>(nv));
  for (int i = 0; i < nv; ++i) other_coordinates[static_cast<std::size_t>(i)] = !robot.moves_feet[static_cast<std::size_t>(i)];
  const bool has_other = std::find(other_coordinates.begin(), other_coordinates.end(), 1) != other_coordinates.end();

  // Swing-foot corners of a solution below the floor at collocation frames whose floor rows were
  // left out (the initial guess had that foot high): flags them; returns how many were added.
  auto add_floor_rows = [&](WindowSpec& spec, const MatX& C_window) {
    int added = 0;
    for (CollocationPoint& p : spec.points) {
      bool evaluated = false;
      for (int foot = 0; foot < 2; ++foot) {
        const auto k = static_cast<std::size_t>(foot);
        if (p.stance[k] >= 0 || p.floor[k]) continue;
        if (!evaluated) {
          VecX x = VecX::Zero(nv);
          for (int m = 0; m < p.support.count; ++m)
            x += p.support.weight[static_cast<std::size_t>(m)] * C_window.col(p.support.index[static_cast<std::size_t>(m)] - spec.first_control);
          VecX q(nq);
          refine::q_from_chart(x, q);
          update_kinematics(model, data, q);
          evaluated = true;
        }
        const Sole& sole = model.soles()[k];
        const Iso3 X = link_pose(model, data, sole.link);
        for (const Vec3& c : sole.corners_L())
          if ((X * c).z() < 0) {
            p.floor[k] = true;
            ++added;
            break;
          }
      }
    }
    return added;
  };

  int failed = 0, iterations = 0, solves = 0, velocity_resolves = 0, floor_resolves = 0;
  double objective = 0, violation = 0, solve_s = 0;
  std::string failures;
  // Solves one stage of a window; when the solution violates a velocity row or a floor row that
  // was left out, adds those rows (and the velocity rows the solution uses beyond
  // velocity_activation of their bound, which the next solve may push over) and solves again from
  // that solution: an active set, at most 5 rounds. Returns false when Ipopt failed or a row is
  // still violated.
  auto solve_stage = [&](WindowSpec& spec, bool contact_rows, MatX& C_out, std::vector<StanceAnchor>& anchors_out,
                         std::string& status) {
    for (int round = 0;; ++round) {
      refine::WindowNlp nlp(robot, data, spec, weights);
      VecX x;
      const refine::IpoptReport r = refine::solve_window(nlp, settings, x);
      ++solves;
      iterations += r.iterations;
      solve_s += r.wall_s;
      status = r.status_text;
      if (!r.success) return false;
      C_out = nlp.controls(x.data());
      anchors_out = nlp.anchors(x.data());
      // Rows in the NLP hold to the solver's constraint tolerance, which the velocity margin covers.
      const bool velocity_ok = nlp.velocity_rows_above(C_out, 1.0, 2 * settings.acceptable_constraint_tolerance).empty();
      const int floor_added = contact_rows ? add_floor_rows(spec, C_out) : 0;
      if ((velocity_ok && floor_added == 0) || round == 4) {
        objective += r.objective;
        violation = std::max(violation, r.constraint_violation);
        if (!velocity_ok) status = "velocity rows still violated after 5 solves";
        return velocity_ok;
      }
      if (!velocity_ok) ++velocity_resolves;
      if (floor_added > 0) ++floor_resolves;
      if (spec.forced_velocity_rows.empty()) spec.forced_velocity_rows.assign(static_cast<std::size_t>(spec.controls.cols() * nv), 0);
      for (int v : nlp.velocity_rows_above(C_out, o.velocity_activation)) spec.forced_velocity_rows[static_cast<std::size_t>(v)] = 1;
      spec.controls = C_out;
      spec.anchors = anchors_out;
    }
  };

  for (std::size_t w = 0; w < windows.size(); ++w) {
    const auto [a, b] = windows[w];
    WindowSpec spec;
    spec.first_control = a;
    spec.num_pinned = w == 0 ? 0 : 3;
    spec.controls = C.middleCols(a, b - a + 1);
    spec.segment_s = stride / fps;
    std::vector<int> local_anchor(phases.size(), -1);
    std::vector<int> anchor_samples;
    for (const CollocationPoint& p : points) {
      const int lo = p.support.index[0], hi = p.support.index[static_cast<std::size_t>(p.support.count - 1)];
      if (lo < a || hi > b || hi < a + spec.num_pinned) continue;
      CollocationPoint local = p;
      for (int foot = 0; foot < 2; ++foot) {
        const int g = p.stance[static_cast<std::size_t>(foot)];
        if (g < 0) continue;
        int& l = local_anchor[static_cast<std::size_t>(g)];
        if (l < 0) {
          l = static_cast<int>(spec.anchors.size());
          StanceAnchor an;
          an.foot = foot;
          an.fixed = phases[static_cast<std::size_t>(g)].anchor_known;
          an.p_W = an.fixed ? phases[static_cast<std::size_t>(g)].anchor : Vec2::Zero();
          spec.anchors.push_back(an);
          anchor_samples.push_back(0);
        }
        local.stance[static_cast<std::size_t>(foot)] = l;
        if (!spec.anchors[static_cast<std::size_t>(l)].fixed) {
          // Initial anchor: mean sole-centre position of the initial guess over the phase.
          update_kinematics(model, data, config_at(C, static_cast<double>(p.frame) / stride, nq));
          const Sole& sole = model.soles()[static_cast<std::size_t>(foot)];
          spec.anchors[static_cast<std::size_t>(l)].p_W += link_point(model, data, sole.link, sole.p_L_center).head<2>();
          ++anchor_samples[static_cast<std::size_t>(l)];
        }
      }
      spec.points.push_back(std::move(local));
    }
    for (std::size_t l = 0; l < spec.anchors.size(); ++l)
      if (!spec.anchors[l].fixed && anchor_samples[l] > 0) spec.anchors[l].p_W /= anchor_samples[l];
    const auto report_failure = [&](const std::string& stage, const std::string& status) {
      ++failed;
      failures += format("%s%d-%d (%s: %s)", failures.empty() ? "" : ", ", std::clamp((a - 1) * stride, 0, T - 1),
                         std::clamp((b - 1) * stride, 0, T - 1), stage.c_str(), status.c_str());
    };

    // Stage 1: root and legs, with the stance and floor constraints.
    WindowSpec feet = spec;
    feet.free_coordinates = feet_coordinates;
    MatX C_feet;
    std::vector<StanceAnchor> anchors;
    std::string status;
    if (!solve_stage(feet, true, C_feet, anchors, status)) {
      report_failure("feet", status);
      continue;  // the window keeps its initial guess
    }
    const int free_cols = b - a + 1 - spec.num_pinned;
    C.middleCols(a + spec.num_pinned, free_cols) = C_feet.rightCols(free_cols);
    for (std::size_t g = 0; g < phases.size(); ++g) {
      const int l = local_anchor[g];
      if (l < 0 || phases[g].anchor_known) continue;
      phases[g].anchor_known = true;
      phases[g].anchor = anchors[static_cast<std::size_t>(l)].p_W;
    }
    if (!has_other) continue;

    // Stage 2: waist, arms and head with the root and legs fixed (no contact rows: they cannot change).
    WindowSpec upper = spec;
    upper.controls = C.middleCols(a, b - a + 1);
    upper.free_coordinates = other_coordinates;
    upper.anchors.clear();
    for (CollocationPoint& p : upper.points) {
      p.stance = {{-1, -1}};
      p.floor = {{false, false}};
    }
    MatX C_upper;
    if (!solve_stage(upper, false, C_upper, anchors, status)) {
      report_failure("upper body", status);
      continue;
    }
    C.middleCols(a + spec.num_pinned, free_cols) = C_upper.rightCols(free_cols);
  }
  if (failed > 0)
    ctx.diagnostics.warn(where, format("refine-ipopt: %d of %zu windows not solved, kept the IK fit there: frames %s", failed,
                                       windows.size(), failures.c_str()));

  // ---- the source-rate motion is the spline ----
  for (int f = 0; f < T; ++f) {
    VecX q = config_at(C, static_cast<double>(f) / stride, nq);
    for (int i = 0; i < model.nu(); ++i) q[7 + i] = std::clamp(q[7 + i], model.q_lower()[i], model.q_upper()[i]);
    motion.q.col(f) = q;
  }
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  // Foot checks at the source rate (quality.hpp measures the same after every pass).
  double drift = 0, penetration = 0;
  std::array<Vec2, 2> start{{Vec2::Zero(), Vec2::Zero()}};
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, motion.q.col(f));
    for (int foot = 0; foot < 2; ++foot) {
      const auto k = static_cast<std::size_t>(foot);
      const Sole& sole = model.soles()[k];
      const Iso3 X = link_pose(model, data, sole.link);
      for (const Vec3& c : sole.corners_L()) penetration = std::max(penetration, -(X * c).z());
      const int g = phase_of[k][static_cast<std::size_t>(f)];
      if (g < 0) continue;
      const Vec2 p = (X * sole.p_L_center).head<2>();
      if (f == phases[static_cast<std::size_t>(g)].begin) start[k] = p;
      drift = std::max(drift, (p - start[k]).norm());
    }
  }

  ctx.statistics.set("stride", stride, "frames", format("knots at %.4g Hz", fps / stride));
  ctx.statistics.set("control-points", N);
  ctx.statistics.set("windows", static_cast<double>(windows.size()));
  ctx.statistics.set("failed-windows", failed, "", failed ? "kept the IK fit" : "");
  ctx.statistics.set("ipopt-solves", solves, "", format("2 stages per window; re-solved with violated velocity rows %d, floor rows %d", velocity_resolves,
                                                        floor_resolves));
  ctx.statistics.set("ipopt-iterations", iterations, "", "all solves");
  ctx.statistics.set("final-objective", objective, "", "sum over solved windows");
  ctx.statistics.set("constraint-violation", violation, "", "max over solved windows [m, rad]");
  ctx.statistics.set("time-per-window", 1e3 * solve_s / static_cast<double>(windows.size()), "ms", "Ipopt solves");
  ctx.statistics.set("collocation-frames", static_cast<double>(points.size()));
  ctx.statistics.set("stance-frames", stance_points, "", "collocation frames x feet held in stance");
  ctx.statistics.set("floor-rows", floor_rows, "", "swing sole corners kept above the floor");
  ctx.statistics.set("jitter-before", jitter_before, "rad/s^3");
  ctx.statistics.set("jitter-after", joint_jitter(motion.q, fps), "rad/s^3");
  ctx.statistics.set("velocity-violations-before", velocity_before, "", "frames x joints");
  ctx.statistics.set("velocity-violations-after", velocity_violations(model, motion.q, fps), "", "frames x joints");
  ctx.statistics.set("stance-drift-max", drift, "m", "sole centre travel in labelled stance, source rate");
  ctx.statistics.set("penetration-max", penetration, "m", "lowest sole corner below the floor, source rate");
  ctx.statistics.set("frames-per-second", T / std::max(total_s, 1e-9), "frames/s", "source frames, refine only");
}

}  // namespace rt
