// retarget inspect: prints what retarget understands of a robot (and, once motion input lands, of
// a clip).

#include <CLI/CLI.hpp>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/model/robot_model.hpp"

namespace rt::cli {

namespace {

struct InspectOptions {
  std::string target;
  std::vector<std::string> package_paths;
};

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Continuous: return "continuous";
    case JointType::Prismatic: return "prismatic";
    case JointType::Fixed: return "fixed";
    case JointType::Floating: return "floating";
  }
  return "?";
}

std::string limit_text(double v) { return std::isfinite(v) ? format("%8.3f", v) : std::string("       -"); }

int inspect_robot(const InspectOptions& o) {
  const auto model = RobotModel::load(o.target, o.package_paths);
  const RobotConfig& c = model->config();
  int fixed = 0;
  for (const Joint& j : model->joints()) fixed += j.type == JointType::Fixed;
  const VecX& q0 = model->standing_q();

  std::cout << "robot " << model->name() << "  (" << c.config_path << ")\n";
  std::cout << "  urdf          " << c.urdf_path << "\n";
  std::cout << format("  structure     %zu links, %d movable joints, %d fixed; nq %d, nv %d\n", model->links().size(),
                      model->nu(), fixed, model->nq(), model->nv());
  std::cout << format("  mass          %.2f kg\n", model->total_mass_kg());
  std::cout << format("  standing      root height %.3f m, COM height %.3f m\n", q0[2], model->standing_com_height_m());
  const char* side[2] = {"left ", "right"};
  for (int s = 0; s < 2; ++s) {
    const Sole& sole = model->soles()[static_cast<std::size_t>(s)];
    std::cout << format("  sole %s    %-24s %.3f x %.3f m, centre (%.3f, %.3f, %.3f) in the link frame\n", side[s],
                        model->links()[static_cast<std::size_t>(sole.link)].name.c_str(), sole.size_m.x(),
                        sole.size_m.y(), sole.p_L_center.x(), sole.p_L_center.y(), sole.p_L_center.z());
  }
  std::cout << "  landmarks     " << c.landmarks.size() << " mapped:";
  for (const LandmarkTarget& t : c.landmarks) std::cout << " " << landmark_name(t.landmark);
  std::cout << "\n\njoints (model order; csv = export column after the 7 root columns)\n";
  std::cout << "   #  csv  name                          type          lower    upper  vel-lim  effort  standing\n";
  std::vector<int> column(static_cast<std::size_t>(model->nu()), -1);
  for (std::size_t k = 0; k < model->export_joint_order().size(); ++k)
    column[static_cast<std::size_t>(model->export_joint_order()[k])] = static_cast<int>(k);
  for (int i = 0; i < model->nu(); ++i) {
    const Joint& j = model->joints()[static_cast<std::size_t>(model->movable_joints()[static_cast<std::size_t>(i)])];
    std::cout << format("  %2d  %3d  %-29s %-11s %s %s %8.2f %7.1f  %8.3f\n", i, column[static_cast<std::size_t>(i)],
                        j.name.c_str(), joint_type_name(j.type), limit_text(model->q_lower()[i]).c_str(),
                        limit_text(model->q_upper()[i]).c_str(), model->velocity_limits()[i],
                        model->effort_limits()[i], q0[7 + i]);
  }
  return kExitOk;
}

}  // namespace

Command setup_inspect(CLI::App& parent) {
  auto opts = std::make_shared<InspectOptions>();
  CLI::App* app = parent.add_subcommand("inspect", "Print what retarget reads from a robot (name, folder or robot.yaml)");
  app->add_option("target", opts->target, "Robot: a name in robots/, a folder or a robot.yaml")->required();
  app->add_option("--package-path", opts->package_paths,
                  "Extra root folder for package:// URIs (repeatable; searched before robot.yaml's and ROS_PACKAGE_PATH)");
  return {app, [opts] { return inspect_robot(*opts); }};
}

}  // namespace rt::cli
