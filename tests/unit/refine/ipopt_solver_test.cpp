#include "src/refine/ipopt_solver.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "small_window.hpp"

namespace rt::refine {
namespace {

using test::SmallWindow;

// Solves the small window; checks the solution satisfies every constraint and lowers the objective.
void solve_and_check(SmallWindow& w, IpoptReport& report) {
  WindowNlp nlp(w.robot, w.data, w.spec, w.weights);
  VecX x0 = nlp.initial_point();
  nlp.evaluate(x0.data());
  const double f0 = nlp.objective();
  VecX x;
  report = solve_window(nlp, IpoptSettings{}, x);
  ASSERT_TRUE(report.success) << report.status_text;
  EXPECT_GT(report.iterations, 0);
  EXPECT_LT(report.constraint_violation, 1e-5);
  EXPECT_LT(report.objective, f0);
  nlp.evaluate(x.data());
  for (int i = 0; i < nlp.num_constraints(); ++i) {
    EXPECT_GE(nlp.constraints()[i], nlp.g_lower()[i] - 1e-5);
    EXPECT_LE(nlp.constraints()[i], nlp.g_upper()[i] + 1e-5);
  }
  for (int i = 0; i < nlp.num_variables(); ++i) {
    EXPECT_GE(x[i], nlp.x_lower()[i]);
    EXPECT_LE(x[i], nlp.x_upper()[i]);
  }
}

TEST(IpoptSolver, SolvesAWindowSilently) {
  SmallWindow w;
  test::build(w, 0, true);
  IpoptReport report;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  solve_and_check(w, report);
  const std::string out = testing::internal::GetCapturedStdout(), err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");  // library code never prints: no banner, no iteration log
  EXPECT_EQ(err, "");
}

// A stray ipopt.opt in the working directory would override options set in code (dependencies.md §5).
TEST(IpoptSolver, IgnoresAnOptionsFileInTheWorkingDirectory) {
  const std::string dir = rt::test::scratch_dir();
  std::ofstream(dir + "/ipopt.opt") << "print_level 5\nmax_iter 1\n";
  const auto previous = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  SmallWindow w;
  test::build(w, 0, false);
  IpoptReport report;
  testing::internal::CaptureStdout();
  solve_and_check(w, report);
  const std::string out = testing::internal::GetCapturedStdout();
  std::filesystem::current_path(previous);
  EXPECT_EQ(out, "");
  EXPECT_GT(report.iterations, 1);
}

TEST(IpoptSolver, ReportsFailureWithoutThrowing) {
  SmallWindow w;
  test::build(w, 0, true);
  WindowNlp nlp(w.robot, w.data, w.spec, w.weights);
  IpoptSettings settings;
  settings.max_iterations = 1;
  VecX x;
  const IpoptReport report = solve_window(nlp, settings, x);
  EXPECT_FALSE(report.success);
  EXPECT_EQ(report.status_text, "Maximum_Iterations_Exceeded");
  EXPECT_EQ(x.size(), nlp.num_variables());
  EXPECT_TRUE(x.allFinite());
}

// Debian's Ipopt + MUMPS crash when two threads solve at once; solve_window serialises them.
TEST(IpoptSolver, ConcurrentSolvesAreSerialised) {
  SmallWindow a, b;
  test::build(a, 0, true);
  test::build(b, 1, true);
  IpoptReport ra, rb;
  std::thread ta([&] { solve_and_check(a, ra); });
  std::thread tb([&] { solve_and_check(b, rb); });
  ta.join();
  tb.join();
  EXPECT_TRUE(ra.success);
  EXPECT_TRUE(rb.success);
}

}  // namespace
}  // namespace rt::refine
