// Where a reference's multibody ZMP comes from: per body group (each leg, each arm, the trunk) the
// part of the ZMP's offset from the COM's ground projection that the group's motion causes, from
// finite differences of the reference's frames (URDF masses and inertias):
//
//     p − c_xy = −Σ_i [ z_i m_i ẍ_i − (x_i − c_x) m_i z̈_i + L̇_i ] / Σ_i m_i (g + z̈_i)   (x; y alike)
//
// with x_i the body's COM and L_i its spin (I_i ω_i, world axes). Prints, over the stance frames and
// over single-support frames, the median size of each group's part and of the whole offset, and how far the
// ZMP lies outside the labelled support. For diagnosing why a reference is not dynamically feasible.
// The per-body sum is also a cross-check of the ZMP metric (passes/quality.hpp, model/centroidal.hpp:
// centroidal momenta on a compact stencil, a frame the floor cannot hold counted as outside): both
// counts of frames more than 1 cm outside are printed. They disagreed by 20-50 % of the stance frames
// of com-plan's walks before the metric's stencil was made compact (2026-12-07).
// With RT_PROBE_FRAMES set, one line per stance frame: time, contacts, the signed distance of the
// metric's ZMP, of the per-body ZMP and of the cart-table ZMP (COM only) from the support, the
// non-COM part's length.
// A reference without a contact schedule (a third-party CSV) is labelled as `retarget validate` labels it.
// Usage: probe_zmp_parts ROBOT REFERENCE(.csv with meta | .npz) [fps for a plain CSV]

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "retarget/jobs/validate_job.hpp"
#include "retarget/model/centroidal.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/passes/quality.hpp"
#include "retarget/passes/stance_support.hpp"
#include "retarget/reference/robot_mapping.hpp"
#include "retarget/sim/reference_signal.hpp"

namespace {

// Group of a MuJoCo body from its name: left/right leg or arm, else trunk.
std::string group_of(const std::string& name) {
  const bool left = name.find("left") != std::string::npos || name.rfind("l_", 0) == 0 || name.rfind("L_", 0) == 0;
  const bool right = name.find("right") != std::string::npos || name.rfind("r_", 0) == 0 || name.rfind("R_", 0) == 0;
  const bool leg = name.find("hip") != std::string::npos || name.find("knee") != std::string::npos ||
                   name.find("ankle") != std::string::npos || name.find("foot") != std::string::npos ||
                   name.find("leg") != std::string::npos || name.find("toe") != std::string::npos ||
                   name.find("thigh") != std::string::npos || name.find("shank") != std::string::npos;
  if (left) return leg ? "left_leg" : "left_arm";
  if (right) return leg ? "right_leg" : "right_arm";
  return "trunk";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rt;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ROBOT REFERENCE [fps]\n", argv[0]);
    return 2;
  }
  try {
    const auto model = RobotModel::load(argv[1]);
    Reference ref = read_reference_for(*model, argv[2], argc > 3 ? std::atof(argv[3]) : 0);
    RobotData data(*model);
    if (!ref.has_contacts()) {  // a third-party reference: labelled as `validate` labels it
      Diagnostics diagnostics;
      const ReferenceRobotMap map(*model, ref, argv[2]);
      ref.contact = label_robot_contacts(*model, data, map.q_all(ref), ref.fps, {}, diagnostics, argv[2]).in_contact;
    }
    const ReferenceSignal signal(*model, data, ref, 0.0);
    const MatX& q = signal.q_frames();
    const int T = static_cast<int>(q.cols());
    const double fps = ref.fps;
    const mjModel* m = model->mj();
    const int nb = m->nbody;
    std::vector<std::string> group(static_cast<std::size_t>(nb));
    std::map<std::string, int> index;
    for (int b = 1; b < nb; ++b) {
      const char* n = mj_id2name(m, mjOBJ_BODY, b);
      group[static_cast<std::size_t>(b)] = group_of(n ? n : "");
      index.emplace(group[static_cast<std::size_t>(b)], 0);
    }
    int gi = 0;
    for (auto& [name, i] : index) i = gi++;
    const int G = gi;
    // Per frame, per body: COM position and spin.
    std::vector<Mat3X> x(static_cast<std::size_t>(T)), spin(static_cast<std::size_t>(T));
    std::vector<Vec3> com(static_cast<std::size_t>(T));
    for (int f = 0; f < T; ++f) {
      const int f0 = std::max(0, f - 1), f1 = std::min(T - 1, f + 1);
      const VecX v = difference(*model, q.col(f0), q.col(f1), (f1 - f0) / fps);
      update_dynamics(*model, data, q.col(f), v);
      const mjData* d = data.mj();
      x[static_cast<std::size_t>(f)].resize(3, nb);
      spin[static_cast<std::size_t>(f)].resize(3, nb);
      com[static_cast<std::size_t>(f)] = com_position(*model, data);
      for (int b = 0; b < nb; ++b) {
        x[static_cast<std::size_t>(f)].col(b) << d->xipos[3 * b], d->xipos[3 * b + 1], d->xipos[3 * b + 2];
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);
        const Vec3 I(m->body_inertia[3 * b], m->body_inertia[3 * b + 1], m->body_inertia[3 * b + 2]);
        const Vec3 w(d->cvel[6 * b], d->cvel[6 * b + 1], d->cvel[6 * b + 2]);
        spin[static_cast<std::size_t>(f)].col(b) = R * I.asDiagonal() * R.transpose() * w;
      }
    }
    const MultibodyZmp metric = multibody_zmp(*model, data, q, fps);
    std::array<std::vector<std::uint8_t>, 2> contact = ref.contact;
    if (contact[0].empty()) contact = signal.contacts();
    // Per [stance, single support] x (group or all) x axis: the parts' sizes over the frames.
    std::vector<std::vector<double>> size(static_cast<std::size_t>(2 * (G + 1) * 2));
    double total_mass = 0;
    for (int b = 1; b < nb; ++b) total_mass += m->body_mass[b];
    int light = 0;
    int n[2] = {0, 0}, outside[2] = {0, 0}, metric_outside[2] = {0, 0};
    double out_sum[2] = {0, 0};
    for (int f = 1; f + 1 < T; ++f) {
      const std::array<bool, 2> down{{contact[0][static_cast<std::size_t>(f)] != 0, contact[1][static_cast<std::size_t>(f)] != 0}};
      if (!down[0] && !down[1]) continue;
      const bool single = down[0] != down[1];
      const Vec3& c = com[static_cast<std::size_t>(f)];
      double Fz = 0;
      std::vector<Vec2> part(static_cast<std::size_t>(G), Vec2::Zero());
      for (int b = 1; b < nb; ++b) {
        const double mb = m->body_mass[b];
        const Vec3 xb = x[static_cast<std::size_t>(f)].col(b);
        const Vec3 a = (x[static_cast<std::size_t>(f + 1)].col(b) - 2 * xb + x[static_cast<std::size_t>(f - 1)].col(b)) * fps * fps;
        const Vec3 Ld = (spin[static_cast<std::size_t>(f + 1)].col(b) - spin[static_cast<std::size_t>(f - 1)].col(b)) * fps / 2;
        Fz += mb * (kGravity + a.z());
        Vec2& p = part[static_cast<std::size_t>(index[group[static_cast<std::size_t>(b)]])];
        p.x() -= xb.z() * mb * a.x() - (xb.x() - c.x()) * mb * a.z() + Ld.y();
        p.y() -= xb.z() * mb * a.y() - (xb.y() - c.y()) * mb * a.z() - Ld.x();
      }
      if (Fz < 0.5 * total_mass * kGravity) ++light;
      Vec2 total = Vec2::Zero();
      for (auto& p : part) {
        p /= Fz;
        total += p;
      }
      update_kinematics(*model, data, q.col(f));
      const SupportPolygon poly = stance_support_polygon(*model, data, down);
      const double dist = poly.signed_distance(c.head<2>() + total);
      const double metric_dist = zmp_distance_outside(poly, metric, f);
      if (std::getenv("RT_PROBE_FRAMES")) {
        const Vec3 cm = (com[static_cast<std::size_t>(f + 1)] - 2 * c + com[static_cast<std::size_t>(f - 1)]) * fps * fps;
        const Vec2 cart = c.head<2>() - c.z() * cm.head<2>() / (kGravity + cm.z());
        std::printf("%6.3f %d %d  metric %7.3f  zmp %7.3f  cart %7.3f  rest %6.3f  parts", f / fps, down[0], down[1], metric_dist,
                    dist, poly.signed_distance(cart),
                    (c.head<2>() + total - cart).norm());
        const Vec2 o = poly.centroid();
        std::printf("  com-centroid (%6.3f %6.3f) zmp-centroid (%6.3f %6.3f)", c.x() - o.x(), c.y() - o.y(), c.x() + total.x() - o.x(),
                    c.y() + total.y() - o.y());
        for (const auto& [name, g] : index) std::printf("  %s %.3f", name.c_str(), part[static_cast<std::size_t>(g)].norm());
        std::printf("\n");
      }
      for (int s = 0; s < (single ? 2 : 1); ++s) {
        ++n[s];
        if (dist > kZmpNear_m) ++outside[s];
        if (metric_dist > kZmpNear_m) ++metric_outside[s];
        out_sum[s] += std::max(dist, 0.0);
        for (int g = 0; g <= G; ++g) {
          const Vec2 p = g < G ? part[static_cast<std::size_t>(g)] : total;
          size[static_cast<std::size_t>(((s * (G + 1)) + g) * 2)].push_back(std::abs(p.x()));
          size[static_cast<std::size_t>(((s * (G + 1)) + g) * 2 + 1)].push_back(std::abs(p.y()));
        }
      }
    }
    auto median = [&](int s, int g, int axis) {
      std::vector<double> v = size[static_cast<std::size_t>(((s * (G + 1)) + g) * 2 + axis)];
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      return 1e3 * v[v.size() / 2];
    };
    std::printf("%d stance frames whose ground force is below half the weight (the body falls faster than g/2)\n", light);
    for (int s = 0; s < 2; ++s) {
      if (n[s] == 0) continue;
      std::printf("%s frames %d: ZMP > 1 cm outside on %d (%.0f %%), mean distance outside %.1f mm; the metric's ZMP on %d (%.0f %%)\n",
                  s ? "single-support" : "stance", n[s], outside[s], 100.0 * outside[s] / n[s], 1e3 * out_sum[s] / n[s],
                  metric_outside[s], 100.0 * metric_outside[s] / n[s]);
      std::printf("  median size of the ZMP offset from the COM projection [mm], x / y:\n");
      for (const auto& [name, g] : index) std::printf("    %-10s %7.1f %7.1f\n", name.c_str(), median(s, g, 0), median(s, g, 1));
      std::printf("    %-10s %7.1f %7.1f\n", "all", median(s, G, 0), median(s, G, 1));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "probe_zmp_parts: %s\n", e.what());
    return 2;
  }
  return 0;
}
