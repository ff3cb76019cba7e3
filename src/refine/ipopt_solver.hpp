#pragma once
/// Ipopt backend of the refine pass (private to rt_refine: no Ipopt header leaks out of
/// ipopt_solver.cpp).
///
/// Thread safety: Debian's Ipopt 3.11 + sequential MUMPS keep global state and crash when two
/// threads solve at once (dependencies.md §5). solve_window() therefore holds one process-wide
/// mutex for the whole solve; callers in several threads are serialised, never concurrent. (Batch
/// jobs that want parallel refinement run clips in separate processes.) The mutex is the one
/// mutable static of rt_refine and guards nothing but Ipopt.
///
/// Ipopt never prints: print_level 0, the banner off (sb yes), options file ignored
/// (Initialize("")). MUMPS is tuned as measured in dependencies.md §5.

#include <string>

#include "src/refine/window_nlp.hpp"

namespace rt::refine {

struct IpoptSettings {
  double tolerance = 1e-6;              ///< Ipopt `tol` (scaled NLP error)
  double constraint_tolerance = 1e-6;   ///< `constr_viol_tol` [m, rad]
  /// "Acceptable" termination: the Gauss–Newton objective Hessian makes the last digits of the dual
  /// infeasibility converge slowly, so a window stops once, for `acceptable_iterations` iterations
  /// in a row, the objective changes by less than `acceptable_objective_change` (relative) and
  /// the constraints hold to `acceptable_constraint_tolerance`.
  int acceptable_iterations = 2;
  double acceptable_objective_change = 1e-4;
  double acceptable_constraint_tolerance = 1e-5;  ///< [m, rad]
  int max_iterations = 100;             ///< `max_iter`
  double mu_init = 1e-3;                ///< initial barrier parameter
  double max_seconds = 60;              ///< `max_cpu_time` per window [s]
};

struct IpoptReport {
  int status = 0;               ///< Ipopt ApplicationReturnStatus
  std::string status_text;      ///< e.g. "Solve_Succeeded"
  bool success = false;         ///< solved (or acceptable) with a finite result
  int iterations = 0;
  double objective = 0;
  double constraint_violation = 0;  ///< max |violation| of constraints and bounds at the result
  double wall_s = 0;
};

/// Solves the window NLP from its initial point; `x` receives the final iterate (the initial point
/// when Ipopt produced none). Exceptions raised while evaluating are rethrown after Ipopt returns.
IpoptReport solve_window(WindowNlp& nlp, const IpoptSettings& settings, VecX& x);

}  // namespace rt::refine
