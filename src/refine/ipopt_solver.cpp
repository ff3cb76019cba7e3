#include "src/refine/ipopt_solver.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>

namespace rt::refine {

namespace {

using Ipopt::Index;
using Ipopt::Number;

// The one lock around Ipopt and MUMPS (see the header). Function-local so that its construction is
// thread-safe and ordered.
std::mutex& ipopt_mutex() {
  static std::mutex m;
  return m;
}

const char* status_name(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition: return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option: return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception: return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown: return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory: return "Insufficient_Memory";
    case Ipopt::Internal_Error: return "Internal_Error";
  }
  return "unknown Ipopt status";
}

// TNLP adapter: forwards to WindowNlp, evaluating once per new x (Ipopt asks for f, g, ∇f, J and H
// at the same x in turn). Exceptions never cross Ipopt: they are kept and rethrown afterwards.
class WindowTnlp final : public Ipopt::TNLP {
 public:
  WindowTnlp(WindowNlp& nlp, VecX& x_out) : nlp_(nlp), x_out_(x_out) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = nlp_.num_variables();
    m = nlp_.num_constraints();
    nnz_jac_g = static_cast<Index>(nlp_.jac_rows().size());
    nnz_h_lag = static_cast<Index>(nlp_.hess_rows().size());
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = std::isfinite(nlp_.x_lower()[i]) ? nlp_.x_lower()[i] : -2e19;
      x_u[i] = std::isfinite(nlp_.x_upper()[i]) ? nlp_.x_upper()[i] : 2e19;
    }
    for (Index i = 0; i < m; ++i) {
      g_l[i] = std::isfinite(nlp_.g_lower()[i]) ? nlp_.g_lower()[i] : -2e19;
      g_u[i] = std::isfinite(nlp_.g_upper()[i]) ? nlp_.g_upper()[i] : 2e19;
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_L, Number* z_U, Index, bool init_lambda,
                          Number* lambda) override {
    if (init_x) {
      const VecX x0 = nlp_.initial_point();
      for (Index i = 0; i < n; ++i) x[i] = x0[i];
    }
    if (init_z)
      for (Index i = 0; i < n; ++i) z_L[i] = z_U[i] = 1.0;
    if (init_lambda)
      for (Index i = 0; i < nlp_.num_constraints(); ++i) lambda[i] = 0.0;
    return true;
  }

  bool eval_f(Index, const Number* x, bool new_x, Number& obj_value) override {
    if (!ensure(x, new_x)) return false;
    obj_value = nlp_.objective();
    return true;
  }
  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* grad_f) override {
    if (!ensure(x, new_x)) return false;
    for (Index i = 0; i < n; ++i) grad_f[i] = nlp_.gradient()[i];
    return true;
  }
  bool eval_g(Index, const Number* x, bool new_x, Index m, Number* g) override {
    if (!ensure(x, new_x)) return false;
    for (Index i = 0; i < m; ++i) g[i] = nlp_.constraints()[i];
    return true;
  }
  bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele_jac, Index* iRow, Index* jCol,
                  Number* values) override {
    if (values == nullptr) {
      for (Index e = 0; e < nele_jac; ++e) {
        iRow[e] = nlp_.jac_rows()[static_cast<std::size_t>(e)];
        jCol[e] = nlp_.jac_cols()[static_cast<std::size_t>(e)];
      }
      return true;
    }
    if (!ensure(x, new_x)) return false;
    for (Index e = 0; e < nele_jac; ++e) values[e] = nlp_.jac_values()[e];
    return true;
  }
  bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda, bool, Index nele_hess,
              Index* iRow, Index* jCol, Number* values) override {
    if (values == nullptr) {
      for (Index e = 0; e < nele_hess; ++e) {
        iRow[e] = nlp_.hess_rows()[static_cast<std::size_t>(e)];
        jCol[e] = nlp_.hess_cols()[static_cast<std::size_t>(e)];
      }
      return true;
    }
    // Gauss–Newton for the objective, exact curvature for the constraints (window_nlp.hpp), constraint part convexified.
    if (!ensure(x, new_x)) return false;
    nlp_.lagrangian_hessian(obj_factor, lambda, values);
    for (Index e = 0; e < nele_hess; ++e)
      if (!std::isfinite(values[e])) return false;
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*, const Number*, Index, const Number*,
                         const Number*, Number obj_value, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_out_ = Eigen::Map<const VecX>(x, n);
    objective_ = obj_value;
    finalized_ = true;
  }

  bool finalized() const { return finalized_; }
  double objective() const { return objective_; }
  std::exception_ptr error() const { return error_; }

 private:
  bool ensure(const Number* x, bool new_x) {
    if (error_) return false;
    if (new_x || !evaluated_) {
      try {
        nlp_.evaluate(x);
      } catch (...) {
        error_ = std::current_exception();
        return false;
      }
      evaluated_ = true;
      valid_ = std::isfinite(nlp_.objective()) && nlp_.gradient().allFinite() && nlp_.constraints().allFinite() &&
               nlp_.jac_values().allFinite() && nlp_.hess_values().allFinite();
    }
    return valid_;
  }

  WindowNlp& nlp_;
  VecX& x_out_;
  bool evaluated_ = false, valid_ = false, finalized_ = false;
  double objective_ = 0;
  std::exception_ptr error_;
};

}  // namespace

IpoptReport solve_window(WindowNlp& nlp, const IpoptSettings& s, VecX& x) {
  IpoptReport report;
  x = nlp.initial_point();
  const auto t0 = std::chrono::steady_clock::now();
  std::exception_ptr error;
  {
    const std::lock_guard<std::mutex> lock(ipopt_mutex());
    Ipopt::SmartPtr<WindowTnlp> tnlp = new WindowTnlp(nlp, x);
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    app->Options()->SetIntegerValue("print_level", 0);
    app->Options()->SetStringValue("sb", "yes");  // no banner
    app->Options()->SetStringValue("print_user_options", "no");
    app->Options()->SetNumericValue("tol", s.tolerance);
    app->Options()->SetNumericValue("constr_viol_tol", s.constraint_tolerance);
    app->Options()->SetIntegerValue("acceptable_iter", s.acceptable_iterations);
    app->Options()->SetNumericValue("acceptable_tol", 1e-1);  // the objective change decides (header)
    app->Options()->SetNumericValue("acceptable_obj_change_tol", s.acceptable_objective_change);
    app->Options()->SetNumericValue("acceptable_constr_viol_tol", s.acceptable_constraint_tolerance);
    app->Options()->SetIntegerValue("max_iter", s.max_iterations);
    app->Options()->SetNumericValue("max_cpu_time", s.max_seconds);
    app->Options()->SetNumericValue("mu_init", s.mu_init);
    app->Options()->SetStringValue("mu_strategy", "adaptive");
    // MUMPS tuning for large sparse windows (dependencies.md §5).
    app->Options()->SetIntegerValue("mumps_mem_percent", 5);
    app->Options()->SetIntegerValue("mumps_permuting_scaling", 0);
    app->Options()->SetIntegerValue("mumps_scaling", 0);
    // AMD ordering: on these block-banded KKT systems it gives the smallest fronts (measured: about
    // 2x faster factorisations than MUMPS' automatic choice).
    app->Options()->SetIntegerValue("mumps_pivot_order", 0);
    // Equalities are the nonlinear stance rows; inequalities hold the linear velocity rows and,
    // unless no swing foot is near the floor, the nonlinear floor rows.
    app->Options()->SetStringValue("jac_c_constant", nlp.num_equalities() == 0 ? "yes" : "no");
    app->Options()->SetStringValue("jac_d_constant", nlp.nonlinear_inequalities() ? "no" : "yes");
    app->Options()->SetStringValue("honor_original_bounds", "yes");
    Ipopt::ApplicationReturnStatus status = app->Initialize("");  // "": a stray ./ipopt.opt is ignored
    if (status == Ipopt::Solve_Succeeded) status = app->OptimizeTNLP(Ipopt::GetRawPtr(tnlp));
    report.status = static_cast<int>(status);
    report.status_text = status_name(status);
    const Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
    if (Ipopt::IsValid(stats)) report.iterations = stats->IterationCount();
    report.objective = tnlp->objective();
    error = tnlp->error();
    report.success = (status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level) &&
                     tnlp->finalized() && x.allFinite() && !error;
  }
  if (error) std::rethrow_exception(error);
  if (!x.allFinite()) x = nlp.initial_point();
  nlp.evaluate(x.data());
  report.objective = nlp.objective();
  report.constraint_violation = nlp.max_violation(x.data());
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace rt::refine
