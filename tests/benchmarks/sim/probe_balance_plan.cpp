// Prints the walking controller's whole-clip balance plan (sim/balance_plan.hpp) of a reference
// next to the reference itself, for diagnosing why a check fails: per sample the contact flags,
// the reference COM, the planned COM and ZMP, the multibody offset Δp and the support's box.
// Usage: [FPS=rate] probe_balance_plan ROBOT REFERENCE(.csv with meta | .npz | plain CSV with FPS) [every_s=0.05]

#include <cstdio>
#include <cstdlib>
#include <string>

#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/jobs/validate_job.hpp"
#include "retarget/sim/balance_plan.hpp"
#include "retarget/sim/dynamics_check.hpp"
#include "retarget/sim/reference_signal.hpp"

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ROBOT REFERENCE [every_s]\n", argv[0]);
    return 2;
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    const double every = argc > 3 ? std::atof(argv[3]) : 0.05;
    const double fps = std::getenv("FPS") ? std::atof(std::getenv("FPS")) : 0;  // a plain CSV needs its rate
    Reference ref = read_reference_for(*model, argv[2], fps);
    RobotData data(*model);
    if (!ref.has_contacts()) {  // labelled as `retarget validate` labels a third-party reference
      Diagnostics diagnostics;
      const ReferenceRobotMap map(*model, ref, argv[2]);
      ref.contact = label_robot_contacts(*model, data, map.q_all(ref), ref.fps, LabelContactsOptions{}, diagnostics, argv[2]).in_contact;
    }
    const DynamicsCheckOptions o = default_check_options(*model);
    const ReferenceSignal signal(*model, data, ref, o.com_smoothing_s);
    BalancePlanOptions po = o.walking.plan;
    po.lead_in_s = o.settle_s;
    const BalancePlan plan = plan_reference_balance(*model, data, signal, po);
    std::printf("max shift %.1f mm at %.2f s, rms %.1f mm, plan violation %.1f mm\n", plan.max_shift_m * 1e3,
                plan.max_shift_time_s, plan.rms_shift_m * 1e3, plan.max_violation_m * 1e3);
    std::printf("    t  L R   ref_x  ref_y  plan_x plan_y  zmp_x  zmp_y   dp_x   dp_y  soleL_x soleL_y z  soleR_x soleR_y z   L_x   L_y   L_z  lowL   lowR\n");
    const TrunkTransform id{};
    for (double t = 0; t <= signal.duration_s() + 1e-9; t += every) {
      const auto c = signal.contact_at(t);
      const Vec3 r = signal.com_at(t, id);
      const Vec2 p = plan.com(t), z = plan.zmp(t), d = plan.offset(t);
      const int k = std::min(signal.num_frames() - 1, static_cast<int>(t * signal.fps() + 0.5));
      const Vec3 sl = signal.soles_W()[0][static_cast<std::size_t>(k)].translation();
      const Vec3 sr = signal.soles_W()[1][static_cast<std::size_t>(k)].translation();
      const int k0 = std::max(0, k - 1), k1 = std::min(signal.num_frames() - 1, k + 1);
      const VecX v = difference(*model, signal.q_frames().col(k0), signal.q_frames().col(k1), (k1 - k0) / signal.fps());
      const CentroidalMomentum L = centroidal_momentum(*model, data, signal.q_frames().col(k), v);
      update_kinematics(*model, data, signal.q_frames().col(k));
      const double low_l = lowest_sole_corner_z(*model, data, 0), low_r = lowest_sole_corner_z(*model, data, 1);
      std::printf("%5.2f  %d %d  %6.3f %6.3f  %6.3f %6.3f  %6.3f %6.3f  %6.3f %6.3f   %6.3f %6.3f %5.3f  %6.3f %6.3f %5.3f  %5.2f %5.2f %5.2f  %6.3f %6.3f\n", t, c[0], c[1],
                  r.x(), r.y(), p.x(), p.y(), z.x(), z.y(), d.x(), d.y(), sl.x(), sl.y(), sl.z(), sr.x(), sr.y(), sr.z(), L.angular_com_W.x(), L.angular_com_W.y(), L.angular_com_W.z(), low_l, low_r);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "probe_balance_plan: %s\n", e.what());
    return 2;
  }
  return 0;
}
