#include "mjcf_writer.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <cstring>
#include <memory>
#include <mutex>
#include <sstream>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt::detail {

namespace {

std::string esc(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string num(double x) { return format("%.17g", x); }
std::string vec(const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

std::string pose_attributes(const Iso3& X) {
  Quat q(X.linear());
  q.normalize();
  std::string s;
  if (!X.translation().isZero(0)) s += " pos=\"" + vec(X.translation()) + "\"";
  if (!q.isApprox(Quat::Identity(), 0))
    s += " quat=\"" + num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z()) + "\"";
  return s;
}

class Writer {
 public:
  explicit Writer(const MjcfModel& m) : m_(m) {}

  std::string run() {
    out_ << "<mujoco model=\"" << esc(m_.model_name) << "\">\n";
    // Inertias come from the URDF only; balanceinertia repairs URDF inertias that violate the
    // triangle inequality (the builder warns about those).
    out_ << "  <compiler angle=\"radian\" inertiafromgeom=\"false\" balanceinertia=\"true\" boundmass=\"0\" "
            "boundinertia=\"0\"/>\n";
    // Contacts come from predefined floor pairs only: the same contacts as the bitmasks select, without
    // the broad phase, which sorted every body each step for pairs that all involve the floor (6% of
    // the dynamics check's time on G1).
    out_ << "  <option timestep=\"" << num(m_.timestep_s)
         << "\" gravity=\"0 0 -9.81\" integrator=\"Euler\" collision=\"predefined\"/>\n";
    out_ << "  <size nconmax=\"100\" njmax=\"500\"/>\n";
    if (!m_.mesh_assets.empty()) {
      out_ << "  <asset>\n";
      for (const auto& name : m_.mesh_assets)
        out_ << "    <mesh name=\"" << esc(name) << "\" file=\"" << esc(name) << ".stl\"/>\n";
      out_ << "  </asset>\n";
    }
    out_ << "  <worldbody>\n";
    out_ << "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\" contype=\"" << m_.floor_contype
         << "\" conaffinity=\"" << m_.floor_conaffinity << "\" condim=\"3\" friction=\"" << num(m_.friction)
         << " 0.005 0.0001\"/>\n";
    body(0, 2);
    out_ << "  </worldbody>\n";
    // A pair's parameters do not come from its geoms: give each what the geoms would mix to (the
    // larger of each, which here are equal).
    out_ << "  <contact>\n";
    for (const MjcfBody& b : m_.bodies)
      for (const MjcfGeom& g : b.geoms)
        out_ << "    <pair geom1=\"floor\" geom2=\"" << esc(g.name) << "\" condim=\"3\" friction=\"" << num(m_.friction) << " "
             << num(m_.friction) << " 0.005 0.0001 0.0001\"/>\n";
    out_ << "  </contact>\n";
    if (!m_.motors.empty()) {
      out_ << "  <actuator>\n";
      for (const auto& mo : m_.motors) {
        out_ << "    <motor name=\"" << esc(mo.joint) << "\" joint=\"" << esc(mo.joint) << "\" gear=\"1\"";
        if (mo.effort_limit > 0) {
          const std::string e = num(mo.effort_limit);
          out_ << " ctrllimited=\"true\" ctrlrange=\"-" << e << " " << e << "\" forcelimited=\"true\" forcerange=\"-" << e
               << " " << e << "\"";
        } else {
          out_ << " ctrllimited=\"false\"";
        }
        out_ << "/>\n";
      }
      out_ << "  </actuator>\n";
    }
    out_ << "</mujoco>\n";
    return out_.str();
  }

 private:
  void body(int index, int depth) {
    const MjcfBody& b = m_.bodies[static_cast<std::size_t>(index)];
    const std::string pad(static_cast<std::size_t>(depth) * 2, ' ');
    out_ << pad << "<body name=\"" << esc(b.name) << "\"" << pose_attributes(b.X_P_B) << ">\n";
    if (b.parent < 0) {
      out_ << pad << "  <freejoint name=\"" << esc(m_.free_joint_name) << "\"/>\n";
    } else {
      const MjcfJoint& j = b.joint;
      out_ << pad << "  <joint name=\"" << esc(j.name) << "\" type=\"" << (j.slide ? "slide" : "hinge") << "\" axis=\""
           << vec(j.axis) << "\"";
      if (j.limited)
        out_ << " limited=\"true\" range=\"" << num(j.lower) << " " << num(j.upper) << "\"";
      else
        out_ << " limited=\"false\"";
      out_ << " armature=\"" << num(j.armature) << "\" damping=\"" << num(j.damping) << "\" frictionloss=\""
           << num(j.frictionloss) << "\"/>\n";
    }
    // Principal axes computed here (Eigen, to full double precision) rather than by MuJoCo from
    // fullinertia, whose iterative diagonalisation is only accurate to about 1e-7.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (b.I_com + b.I_com.transpose()));
    Mat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) *= -1;
    Iso3 X_B_I = Iso3::Identity();
    X_B_I.linear() = axes;
    X_B_I.translation() = b.p_B_com;
    std::string pose = pose_attributes(X_B_I);
    if (b.p_B_com.isZero(0)) pose = " pos=\"0 0 0\"" + pose;
    out_ << pad << "  <inertial" << pose << " mass=\"" << num(b.mass_kg) << "\" diaginertia=\"" << vec(eig.eigenvalues())
         << "\"/>\n";
    for (const MjcfGeom& g : b.geoms) {
      out_ << pad << "  <geom name=\"" << esc(g.name) << "\"";
      switch (g.kind) {
        case MjcfGeom::Kind::Box: out_ << " type=\"box\" size=\"" << vec(g.half_size) << "\""; break;
        case MjcfGeom::Kind::Sphere: out_ << " type=\"sphere\" size=\"" << num(g.half_size.x()) << "\""; break;
        case MjcfGeom::Kind::Cylinder:
          out_ << " type=\"cylinder\" size=\"" << num(g.half_size.x()) << " " << num(g.half_size.y()) << "\"";
          break;
        case MjcfGeom::Kind::Mesh: out_ << " type=\"mesh\" mesh=\"" << esc(g.mesh) << "\""; break;
      }
      out_ << pose_attributes(g.X_B_G) << " group=\"" << g.group << "\" contype=\"" << m_.robot_contype
           << "\" conaffinity=\"" << m_.robot_conaffinity << "\" condim=\"3\" friction=\"" << num(m_.friction)
           << " 0.005 0.0001\"/>\n";
    }
    for (int c : b.children) body(c, depth + 1);
    out_ << pad << "</body>\n";
  }

  const MjcfModel& m_;
  std::ostringstream out_;
};

// MuJoCo's XML parser, compiler and its error/warning hooks are process-wide state.
std::mutex& mujoco_loader_mutex() {
  static std::mutex m;
  return m;
}

void drop_warning(const char*) {}
void throw_error(const char* message) { throw InternalError(std::string("MuJoCo error: ") + message); }

struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};

}  // namespace

std::string write_mjcf(const MjcfModel& model) { return Writer(model).run(); }

void install_mujoco_hooks() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!mju_user_warning) mju_user_warning = &drop_warning;
    if (!mju_user_error) mju_user_error = &throw_error;
  });
}

mjModel* compile_mjcf(const std::string& xml, const std::vector<MjcfFile>& files, const std::string& location,
                      std::string& warning) {
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  auto add = [&](const std::string& name, const std::string& bytes) {
    if (bytes.size() > static_cast<std::size_t>(1) << 30) throw InputError(location, "mesh '" + name + "' is too large");
    const int rc = mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(bytes.size()));
    if (rc == 1) throw InputError(location, "too many meshes for MuJoCo's virtual file system (at most 1999)");
    if (rc == 2) throw InternalError("duplicate VFS file name " + name);
    const int id = mj_findFileVFS(vfs.get(), name.c_str());
    RT_DEMAND(id >= 0, "VFS file just added is missing");
    std::memcpy(vfs->filedata[id], bytes.data(), bytes.size());
  };
  add("model.xml", xml);
  for (const auto& f : files) add(f.name, f.bytes);

  std::lock_guard<std::mutex> lock(mujoco_loader_mutex());
  install_mujoco_hooks();
  char error[2048] = "";
  mjModel* m = mj_loadXML("model.xml", vfs.get(), error, sizeof error);
  std::string msg(error);
  for (char& c : msg)
    if (c == '\n' || c == '\r') c = ' ';
  msg = std::string(trim(msg));
  if (!m) throw InputError(location, "MuJoCo rejected the generated model: " + msg);
  warning = msg;
  return m;
}

}  // namespace rt::detail
