#include "retarget/reference/npz_layout.hpp"

#include <map>
#include <set>

#include "formats/mjcf/mjcf_tree.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"
#include "retarget/core/yaml_view.hpp"
#include "retarget/model/kinematics.hpp"
#include "retarget/model/robot_model.hpp"
#include "retarget/reference/robot_mapping.hpp"

namespace rt {

namespace {

const std::string& joint_name(const RobotModel& model, int movable) {
  return model.joints()[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(movable)])].name;
}

std::vector<std::string> export_order(const RobotModel& model) {
  std::vector<std::string> out;
  for (int k : model.export_joint_order()) out.push_back(joint_name(model, k));
  return out;
}

std::vector<int> urdf_bodies(const RobotModel& model) {
  std::vector<int> links = {model.root_link()};
  for (int l = 0; l < static_cast<int>(model.links().size()); ++l)
    if (l != model.root_link()) links.push_back(l);
  return links;
}

// Checks that `names` lists every movable joint of the robot once; `where_of(i)` locates entry i.
template <typename Where>
void check_joint_set(const RobotModel& model, const std::vector<std::string>& names, Where where_of,
                     const std::string& where_all) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const int j = model.find_joint(names[i]);
    if (j < 0 || model.joints()[static_cast<std::size_t>(j)].qpos_index < 0)
      throw InputError(where_of(i), "'" + names[i] + "' is not a movable joint of robot " + model.name());
    if (!seen.insert(names[i]).second) throw InputError(where_of(i), "joint '" + names[i] + "' is listed twice");
  }
  for (int k = 0; k < model.nu(); ++k)
    if (!seen.count(joint_name(model, k)))
      throw InputError(where_all, format("robot %s joint '%s' is missing (%zu of %d joints listed)", model.name().c_str(),
                                         joint_name(model, k).c_str(), names.size(), model.nu()));
}

NpzLayout mjcf_layout(const RobotModel& model, const std::string& path) {
  const MjcfTree tree = read_mjcf_tree(path);
  NpzLayout layout;
  for (std::size_t b = 0; b < tree.bodies.size(); ++b) {
    const MjcfBody& body = tree.bodies[b];
    const std::string where = tree.where(body.line);
    const int link = model.find_link(body.name);
    if (link < 0)
      throw InputError(where, "body '" + body.name + "' is not a link of robot " + model.name() + "'s URDF");
    if (b == 0 && link != model.root_link())
      throw InputError(where, "the first body '" + body.name + "' is not the URDF root link '" +
                                  model.links()[static_cast<std::size_t>(model.root_link())].name + "'");
    layout.body_links.push_back(link);
    // The MJCF nests bodies as the URDF does, up to merged fixed links: the body's parent must be
    // the nearest URDF ancestor link that is a body of the MJCF.
    if (body.parent >= 0) {
      const std::string& parent_name = tree.bodies[static_cast<std::size_t>(body.parent)].name;
      std::string urdf_parent;
      for (int l = link;;) {
        const int pj = model.links()[static_cast<std::size_t>(l)].parent_joint;
        if (pj < 0) break;
        l = model.joints()[static_cast<std::size_t>(pj)].parent_link;
        if (model.links()[static_cast<std::size_t>(l)].name == parent_name) {
          urdf_parent = parent_name;
          break;
        }
      }
      if (urdf_parent.empty())
        throw InputError(where, "body '" + body.name + "' is inside body '" + parent_name + "', which is not above link '" +
                                    body.name + "' in the URDF");
    }
    for (const MjcfJoint& j : body.joints) {
      if (j.type == "free") {
        if (b != 0) throw InputError(tree.where(j.line), "a free joint on body '" + body.name + "', not on the root body");
        continue;
      }
      const int uj = model.find_joint(j.name);
      if (uj < 0 || model.joints()[static_cast<std::size_t>(uj)].qpos_index < 0)
        throw InputError(tree.where(j.line), "joint '" + j.name + "' is not a movable joint of robot " + model.name());
      if (model.joints()[static_cast<std::size_t>(uj)].child_link != link)
        throw InputError(tree.where(j.line), "joint '" + j.name + "' is in body '" + body.name + "' but moves link '" +
                                                 model.links()[static_cast<std::size_t>(model.joints()[static_cast<std::size_t>(uj)].child_link)].name +
                                                 "' in the URDF");
      layout.joint_order.push_back(j.name);
    }
  }
  std::vector<int> lines;
  for (const MjcfJoint* j : tree.movable_joints()) lines.push_back(j->line);
  check_joint_set(
      model, layout.joint_order, [&](std::size_t i) { return tree.where(lines[i]); }, tree.file);
  return layout;
}

// A YAML list of joint names, located per entry.
std::vector<std::string> yaml_joints(const RobotModel& model, const YamlView& list) {
  list.expect_sequence();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) names.push_back(list.at(i).as_string());
  check_joint_set(
      model, names, [&](std::size_t i) { return list.at(i).location() + ": " + list.at(i).path(); },
      list.location() + ": " + list.path());
  return names;
}

NpzLayout names_layout(const RobotModel& model, const std::string& path) {
  const YamlView doc = YamlView::load_file(path);
  doc.expect_map();
  doc.check_keys({"bodies", "joints"});
  NpzLayout layout;
  if (auto bodies = doc.find("bodies")) {
    bodies->expect_sequence();
    if (bodies->size() == 0) bodies->fail("expected at least one body");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < bodies->size(); ++i) {
      const YamlView item = bodies->at(i);
      const std::string name = item.as_string();
      const int link = model.find_link(name);
      if (link < 0) item.fail("'" + name + "' is not a link of robot " + model.name() + "'s URDF");
      if (!seen.insert(name).second) item.fail("body '" + name + "' is listed twice");
      layout.body_links.push_back(link);
    }
  } else {
    layout.body_links = urdf_bodies(model);
  }
  layout.joint_order = doc.has("joints") ? yaml_joints(model, doc.at("joints")) : export_order(model);
  return layout;
}

}  // namespace

NpzLayout resolve_npz_layout(const RobotModel& model, const std::string& spec, const std::string& where) {
  NpzLayout layout;
  if (spec == "urdf") {
    layout.body_links = urdf_bodies(model);
    layout.joint_order = export_order(model);
  } else if (starts_with(spec, "mjcf:") && spec.size() > 5) {
    layout = mjcf_layout(model, spec.substr(5));
  } else if (starts_with(spec, "names:") && spec.size() > 6) {
    layout = names_layout(model, spec.substr(6));
  } else {
    throw InputError(where, "expected urdf, mjcf:FILE or names:FILE, got '" + spec + "'");
  }
  layout.spec = spec;
  return layout;
}

std::vector<std::string> read_joint_order(const RobotModel& model, const std::string& path) {
  if (ends_with(to_lower(path), ".xml")) return mjcf_layout(model, path).joint_order;
  const YamlView doc = YamlView::load_file(path);
  if (doc.is_sequence()) return yaml_joints(model, doc);
  doc.expect_map();
  doc.check_keys({"bodies", "joints"});
  return yaml_joints(model, doc.at("joints"));
}

NpzBodyArrays compute_body_arrays(const RobotModel& model, RobotData& data, const Reference& ref, const NpzLayout& layout) {
  const ReferenceRobotMap map(model, ref, "reference");
  const int T = ref.num_frames();
  const std::vector<int>& links = layout.body_links;
  NpzBodyArrays b;
  b.joint_order = layout.joint_order;
  const std::size_t B = links.size();
  b.p_W_body.assign(B, Mat3X(3, T));
  b.q_W_body.assign(B, std::vector<Quat>(static_cast<std::size_t>(T)));
  b.v_W_body.assign(B, Mat3X(3, T));
  b.w_W_body.assign(B, Mat3X(3, T));
  for (int l : links) b.body_names.push_back(model.links()[static_cast<std::size_t>(l)].name);
  for (int f = 0; f < T; ++f) {
    update_kinematics(model, data, map.q(ref, f));
    for (std::size_t k = 0; k < B; ++k) {
      const Iso3 X = link_pose(model, data, links[k]);
      b.p_W_body[k].col(f) = X.translation();
      Quat q(X.linear());
      q.normalize();
      // Keep each body's quaternion sign continuous over time.
      if (f > 0 && q.coeffs().dot(b.q_W_body[k][static_cast<std::size_t>(f - 1)].coeffs()) < 0) q.coeffs() *= -1;
      b.q_W_body[k][static_cast<std::size_t>(f)] = q;
    }
  }
  for (std::size_t k = 0; k < B; ++k) {
    for (int f = 0; f < T; ++f) {
      const int a = std::max(0, f - 1), c = std::min(T - 1, f + 1);
      if (c == a) {
        b.v_W_body[k].col(f).setZero();
        b.w_W_body[k].col(f).setZero();
        continue;
      }
      const double dt = (c - a) / ref.fps;
      b.v_W_body[k].col(f) = (b.p_W_body[k].col(c) - b.p_W_body[k].col(a)) / dt;
      const AngleAxis d(b.q_W_body[k][static_cast<std::size_t>(c)] * b.q_W_body[k][static_cast<std::size_t>(a)].inverse());
      b.w_W_body[k].col(f) = d.angle() * d.axis() / dt;
    }
  }
  return b;
}

}  // namespace rt
