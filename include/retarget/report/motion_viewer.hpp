#pragma once
/// The motion viewer: one self-contained HTML page that shows a robot reference in 3-D (README
/// "view"). The page inlines three.js from Debian's libjs-three package and the
/// scene data, so it opens offline from any folder and fetches nothing.
///
/// What the page draws: the robot's meshes (URDF visual geometry, else collision geometry,
/// decimated to a face budget) posed per frame; the floor; the feet coloured while in contact,
/// a contact timeline and the support polygon (convex hull of the soles in contact) on the floor;
/// the kinematic COM and, when the reference has them (meta.json / NPZ `com_pos_w`, `zmp_w`),
/// the planned COM and ZMP (predicted COP) with their floor traces; optionally the source human
/// skeleton (landmarks scaled to the robot) over or beside the robot; for the robot page, the
/// standing pose with its soles and landmarks. Controls: play/pause, time scrubber, speed, keys, layer checkboxes.
///
/// The scene is computed here (forward kinematics per frame, in C++), so the page's script only
/// places meshes: link poses, sole corners and points are embedded as little-endian float32
/// arrays in base64 inside a JSON block <script type="application/json" id="rt-viewer-data">.
/// parse_viewer_page reads that block back (tests, and anyone scripting around the page).
///
/// Frames and units: W = world, z up, floor at z = 0, metres; frame k at t = k / fps.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "retarget/core/types.hpp"
#include "retarget/motion/human_motion.hpp"
#include "retarget/reference/reference.hpp"

namespace rt {

class RobotModel;

/// Where the page's JavaScript libraries come from (Debian libjs-three).
inline constexpr const char* kThreeJsPackage = "libjs-three";
inline constexpr const char* kThreeJsDefaultDir = "/usr/share/javascript/three";

/// A triangle mesh attached to a link, in that link's frame [m].
struct ViewerMesh {
  int link = -1;                       ///< index into ViewerScene::link_names
  std::vector<float> positions_L;      ///< x y z per vertex
  std::vector<std::uint32_t> indices;  ///< 3 per triangle
  std::array<float, 3> color{0.7f, 0.7f, 0.72f};  ///< linear RGB 0..1
  int num_triangles() const { return static_cast<int>(indices.size() / 3); }
};

/// Named points per frame (the source skeleton, the robot's landmarks).
struct ViewerPoints {
  std::vector<std::string> names;               ///< N
  std::vector<std::array<int, 2>> bones;        ///< segments between points (indices into names)
  std::vector<float> p_W;                       ///< T x N x 3 [m] (T = 1 for a still scene)
  std::vector<std::uint8_t> valid;              ///< T x N, 1 = the point exists at that frame
  bool empty() const { return names.empty(); }
};

/// Everything the page shows, per frame where it moves. T = num_frames, L = link_names.size().
struct ViewerScene {
  std::string mode = "motion";          ///< "motion" (a reference) or "robot" (the standing pose)
  std::string title;
  std::string robot;
  double fps = 30;                      ///< [Hz]
  int num_frames = 0;
  std::vector<std::string> link_names;  ///< links that carry a mesh or a sole
  std::vector<float> link_poses;        ///< T x L x 7: p_W x y z, quat_W x y z w
  std::vector<ViewerMesh> meshes;
  std::string mesh_source;              ///< "visual", "collision" or "visual+collision"
  std::array<int, 2> foot_links{-1, -1};   ///< [left, right] indices into link_names
  std::vector<float> sole_corners_W;    ///< T x 2 x 4 x 3 [m], counter-clockwise from above
  std::array<std::vector<std::uint8_t>, 2> contact;  ///< per foot T flags; empty when unknown
  std::vector<float> com_W;             ///< T x 3 [m] kinematic COM of the posed robot
  std::vector<float> com_planned_W;     ///< T x 3 [m] planned COM; empty when absent
  std::vector<float> cop_planned_W;     ///< T x 2 [m] planned ZMP / predicted COP; empty when absent
  ViewerPoints skeleton;                ///< source human (scaled landmarks); empty when absent
  ViewerPoints landmarks;               ///< robot landmark points (robot mode); empty otherwise
  std::vector<std::string> notes;       ///< shown on the page (meshes replaced, faces dropped, ...)

  int num_links() const { return static_cast<int>(link_names.size()); }
  int num_triangles() const;
};

struct ViewerOptions {
  std::string title;                 ///< page title; default "<robot>: <reference file>"
  bool collision_meshes = false;     ///< draw collision instead of visual geometry
  /// Total triangle budget of the robot's meshes, shared among the meshes in proportion to
  /// their own counts (vertex clustering, simplify_mesh; a mesh keeps at least 12). At 60000 the
  /// G1's 393270 visual triangles become 47901 (1.1 MB in the page), still recognisable.
  int max_triangles = 60000;
  std::string three_js_dir = kThreeJsDefaultDir;  ///< folder of three.min.js (libjs-three)
  /// [Hz] The page plays at most this rate: a faster reference keeps every n-th frame (n the
  /// smallest with fps / n <= max_fps), which bounds the page size per second of motion.
  double max_fps = 60;
};

/// The source human skeleton for a scene: landmark tracks (W, metres, robot proportions: the
/// scale pass's LandmarkTargets, at `fps_tracks`, the rate of the robot motion the reference was
/// resampled from) sampled at the scene's frame times k / scene.fps by linear interpolation, with
/// bones between the usual anatomical neighbours. A point is valid where both neighbouring
/// samples are.
ViewerPoints skeleton_points(const std::array<LandmarkTrack, kLandmarkCount>& tracks, double fps_tracks,
                             const ViewerScene& scene);

/// The scene of a reference played on `model`: per-frame FK of every link with geometry, soles,
/// COM, and the reference's contacts, COM and COP. InputError "<where> ..." when the reference's
/// joints are not the robot's or it has no frames; InputError naming the mesh file when a mesh
/// cannot be read (a visual mesh that fails falls back to the link's collision geometry, with a
/// note).
ViewerScene motion_scene(const RobotModel& model, const Reference& reference, const std::string& where,
                         const ViewerOptions& options = {});

/// The robot in its standing pose: one frame, both feet in contact, the robot's landmark points.
ViewerScene robot_scene(const RobotModel& model, const ViewerOptions& options = {});

/// The HTML page of a scene, with three.js inlined from options.three_js_dir. InputError
/// "<dir>/three.min.js: not found; install the Debian package libjs-three ..." when it is missing.
std::string viewer_page_html(const ViewerScene& scene, const ViewerOptions& options = {});

/// Throws that same InputError now when three.js is missing (before a long conversion).
void require_three_js(const ViewerOptions& options);

/// Reads the scene back from a page written by viewer_page_html (the data block only; meshes'
/// colours and notes included). InputError "<file>: ..." when the block is missing or malformed.
ViewerScene parse_viewer_page(const std::string& html, const std::string& file);

/// Standard base64 (RFC 4648, with padding) of bytes, and its inverse (InputError "<where>: ..."
/// on a character outside the alphabet or a bad length).
std::string base64_encode(const void* data, std::size_t bytes);
std::string base64_decode(const std::string& text, const std::string& where);

}  // namespace rt
