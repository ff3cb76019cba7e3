#include "formats/reference/reference_npz.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "formats/reference/npz_file.hpp"
#include "formats/reference/reference_csv.hpp"
#include "formats/reference/reference_meta.hpp"
#include "retarget/core/error.hpp"
#include "retarget/core/limits.hpp"
#include "retarget/core/file_io.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

namespace {

using npz::Array;
using npz::DType;
using npz::NamedArray;

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

void check_body_arrays(const NpzBodyArrays& b, int T) {
  const std::size_t B = b.body_names.size();
  RT_DEMAND(B > 0, "NpzBodyArrays without bodies");
  RT_DEMAND(b.p_W_body.size() == B && b.q_W_body.size() == B, "NpzBodyArrays: one position and orientation track per body");
  RT_DEMAND(b.v_W_body.empty() || b.v_W_body.size() == B, "NpzBodyArrays: v_W_body empty or one per body");
  RT_DEMAND(b.w_W_body.empty() || b.w_W_body.size() == B, "NpzBodyArrays: w_W_body empty or one per body");
  std::set<std::string> names;
  for (std::size_t i = 0; i < B; ++i) {
    RT_DEMAND(!b.body_names[i].empty() && names.insert(b.body_names[i]).second, "NpzBodyArrays: body names unique, non-empty");
    RT_DEMAND(b.p_W_body[i].cols() == T && b.q_W_body[i].size() == static_cast<std::size_t>(T),
              "NpzBodyArrays: body tracks need one column per reference frame");
    RT_DEMAND(b.v_W_body.empty() || b.v_W_body[i].cols() == T, "NpzBodyArrays: v_W_body frame count");
    RT_DEMAND(b.w_W_body.empty() || b.w_W_body[i].cols() == T, "NpzBodyArrays: w_W_body frame count");
  }
}

// (T, B, width) array from per-body width x T tracks; `get(b, t, i)` gives one value.
template <typename Get>
std::vector<double> per_frame_body(int T, std::size_t B, int width, const std::vector<std::string>& names,
                                   const char* key, Get get) {
  std::vector<double> v(static_cast<std::size_t>(T) * B * static_cast<std::size_t>(width));
  std::size_t k = 0;
  for (int t = 0; t < T; ++t)
    for (std::size_t b = 0; b < B; ++b)
      for (int i = 0; i < width; ++i) {
        const double x = get(b, t, i);
        if (!std::isfinite(x))
          throw InputError(format("body arrays [%s] frame %d body %s", key, t, names[b].c_str()), "non-finite value");
        v[k++] = x;
      }
  return v;
}

// Reads and checks the arrays of one NPZ reference.
class NpzReferenceReader {
 public:
  NpzReferenceReader(const npz::NpzFile& f, const ReferenceReadOptions& o) : f_(f), o_(o) {}

  Reference read(NpzBodyArrays* bodies) {
    Reference r;
    const Array& fps = require("fps");
    numeric("fps", fps);
    if (fps.size() != 1 || fps.ndim() > 1) fail("fps", "expected one value, shape " + shape_text(fps.shape));
    r.fps = fps.number(0);
    if (!(r.fps >= kMinFrameRate_hz && r.fps <= kMaxFrameRate_hz))
      fail("fps", format("the frame rate is %.6g Hz, not %s", r.fps, range_in_words(kMinFrameRate_hz, kMaxFrameRate_hz, "Hz").c_str()));

    const Array& q = require("joint_pos");
    numeric("joint_pos", q);
    if (q.ndim() != 2 || q.shape[0] < 1 || q.shape[1] < 1)
      fail("joint_pos", "expected shape (T, J) with T, J >= 1, got " + shape_text(q.shape));
    if (q.shape[0] > static_cast<std::size_t>(std::numeric_limits<int>::max()) || q.shape[1] > 100000)
      fail("joint_pos", "absurd shape " + shape_text(q.shape));
    T_ = q.shape[0];
    const std::size_t J = q.shape[1];

    if (const Array* names = f_.find("joint_names")) {
      if (names->dtype != DType::Unicode) fail("joint_names", "expected a string array, got dtype " + names->descr());
      expect_shape("joint_names", *names, {J});
      r.joint_names = names->to_strings();
      std::set<std::string> seen;
      for (const std::string& n : r.joint_names)
        if (n.empty() || !seen.insert(n).second) fail("joint_names", "empty or duplicate joint name '" + n + "'");
    } else if (o_.npz_joint_order.empty()) {
      // Guessing the robot's own order would silently train or check the wrong joints when the
      // file came from a simulator with another order: the user states it.
      fail("joint_names", "missing: this NPZ does not name its joints; state their order with --joint-order FILE "
                          "(the MJCF or a YAML list of joint names the file was written in)");
    } else if (o_.npz_joint_order.size() != J) {
      fail("joint_pos", format("%zu joint columns but the stated joint order has %zu joints (the file has no joint_names)",
                               J, o_.npz_joint_order.size()));
    } else {
      r.joint_names = o_.npz_joint_order;
    }
    joint_names_ = &r.joint_names;

    r.joint_pos = matrix("joint_pos", q, J, Label::Joint);
    if (const Array* v = f_.find("joint_vel")) {
      numeric("joint_vel", *v);
      expect_shape("joint_vel", *v, {T_, J});
      matrix("joint_vel", *v, J, Label::Joint);  // checked (finite), not kept: it derives from joint_pos
    }

    // Body arrays first: body 0 may provide the root pose.
    NpzBodyArrays local;
    NpzBodyArrays& b = bodies ? *bodies : local;
    read_bodies(b);
    b.joint_order = r.joint_names;

    const Array* root_pos = f_.find("root_pos_w");
    const Array* root_quat = f_.find("root_quat_w");
    if ((root_pos == nullptr) != (root_quat == nullptr))
      fail(root_pos ? "root_quat_w" : "root_pos_w", "missing: root_pos_w and root_quat_w come together");
    if (root_pos) {
      numeric("root_pos_w", *root_pos);
      expect_shape("root_pos_w", *root_pos, {T_, 3});
      r.root_pos_W = matrix("root_pos_w", *root_pos, 3, Label::Axis);
      numeric("root_quat_w", *root_quat);
      expect_shape("root_quat_w", *root_quat, {T_, 4});
      r.root_quat_W = quaternions("root_quat_w", matrix("root_quat_w", *root_quat, 4, Label::Axis));
    } else if (!b.empty()) {
      r.root_pos_W = b.p_W_body[0];
      r.root_quat_W = b.q_W_body[0];
    } else {
      fail("root_pos_w", "missing root pose: expected root_pos_w and root_quat_w (or body_pos_w and body_quat_w, "
                         "whose body 0 is the root)");
    }

    if (const Array* c = f_.find("contacts")) {
      numeric("contacts", *c);
      expect_shape("contacts", *c, {T_, 2});
      for (std::size_t foot = 0; foot < 2; ++foot) r.contact[foot].resize(T_);
      for (std::size_t t = 0; t < T_; ++t)
        for (std::size_t foot = 0; foot < 2; ++foot) {
          const double v = c->number(2 * t + foot);
          if (v != 0 && v != 1)
            throw InputError(value_loc("contacts", t) + (foot ? " right" : " left"), format("contact flag %g is not 0 or 1", v));
          r.contact[foot][t] = static_cast<std::uint8_t>(v);
        }
    }
    if (const Array* c = f_.find("com_pos_w")) {
      numeric("com_pos_w", *c);
      expect_shape("com_pos_w", *c, {T_, 3});
      r.com_W = matrix("com_pos_w", *c, 3, Label::Axis);
    }
    for (const char* key : {"zmp_w", "cop_ref_w"}) {  // the same plan under both names; zmp_w wins
      if (const Array* c = f_.find(key)) {
        numeric(key, *c);
        expect_shape(key, *c, {T_, 2});
        r.cop_W = matrix(key, *c, 2, Label::Axis);
        break;
      }
    }
    for (const char* key : {"time_s", "time"}) {
      if (const Array* t = f_.find(key)) {
        numeric(key, *t);
        expect_shape(key, *t, {T_});
        check_time_stamps(t->to_doubles(), r.fps, f_.location(key));
      }
    }
    return r;
  }

 private:
  enum class Label { Joint, Axis, Body };

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(f_.location(key), what);
  }
  const Array& require(const std::string& key) const {
    const Array* a = f_.find(key);
    if (!a) throw InputError(f_.file + " [" + key + ".npy]", "missing required array '" + key + "'");
    return *a;
  }
  void numeric(const std::string& key, const Array& a) const {
    if (!a.is_numeric()) fail(key, "expected a numeric array, got dtype " + a.descr());
  }
  void expect_shape(const std::string& key, const Array& a, const std::vector<std::size_t>& shape) const {
    if (a.shape != shape) {
      std::string want = shape_text(shape);
      fail(key, "shape " + shape_text(a.shape) + " where " + want + " is expected (T = " + std::to_string(T_) + ")");
    }
  }
  std::string value_loc(const std::string& key, std::size_t t) const {
    return format("%s [%s] frame %zu", f_.file.c_str(), key.c_str(), t);
  }
  // (T, width) array -> width x T matrix, every value finite.
  MatX matrix(const std::string& key, const Array& a, std::size_t width, Label label) const {
    MatX m(static_cast<Eigen::Index>(width), static_cast<Eigen::Index>(T_));
    for (std::size_t t = 0; t < T_; ++t)
      for (std::size_t i = 0; i < width; ++i) {
        const double v = a.number(t * width + i);
        if (!std::isfinite(v)) {
          std::string what = value_loc(key, t);
          if (label == Label::Joint) what += " joint " + (*joint_names_)[i];
          if (label == Label::Axis) what += format(" column %zu", i);
          throw InputError(what, std::isnan(v) ? "NaN is not allowed" : "infinite value");
        }
        m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(t)) = v;
      }
    return m;
  }
  // 4 x T w x y z columns -> unit quaternions (tolerance check, normalised as in the CSV reader).
  std::vector<Quat> quaternions(const std::string& key, const MatX& wxyz) const {
    std::vector<Quat> out(static_cast<std::size_t>(wxyz.cols()));
    for (Eigen::Index t = 0; t < wxyz.cols(); ++t) {
      const Quat q(wxyz(0, t), wxyz(1, t), wxyz(2, t), wxyz(3, t));
      const double n = q.norm();
      if (!(std::fabs(n - 1.0) <= o_.quat_norm_tolerance))
        throw InputError(value_loc(key, static_cast<std::size_t>(t)),
                         format("quaternion (w x y z) has norm %.9g; expected a unit quaternion (tolerance %g)", n,
                                o_.quat_norm_tolerance));
      out[static_cast<std::size_t>(t)] = canonical_unit_quat(q);
    }
    return out;
  }

  void read_bodies(NpzBodyArrays& b) const {
    b = NpzBodyArrays();
    const Array* pos = f_.find("body_pos_w");
    const Array* quat = f_.find("body_quat_w");
    const Array* names = f_.find("body_names");
    const Array* lin = f_.find("body_lin_vel_w");
    const Array* ang = f_.find("body_ang_vel_w");
    if (!pos && !quat && !names && !lin && !ang) return;
    if (!pos || !quat)
      fail(pos ? "body_quat_w" : "body_pos_w", "missing: body arrays need both body_pos_w and body_quat_w");
    numeric("body_pos_w", *pos);
    if (pos->ndim() != 3 || pos->shape[0] != T_ || pos->shape[1] < 1 || pos->shape[2] != 3)
      fail("body_pos_w", "shape " + shape_text(pos->shape) + " where (T, B, 3) is expected (T = " + std::to_string(T_) + ")");
    const std::size_t B = pos->shape[1];
    if (names) {
      if (names->dtype != DType::Unicode) fail("body_names", "expected a string array, got dtype " + names->descr());
      expect_shape("body_names", *names, {B});
      b.body_names = names->to_strings();
      std::set<std::string> seen;
      for (const std::string& n : b.body_names)
        if (n.empty() || !seen.insert(n).second) fail("body_names", "empty or duplicate body name '" + n + "'");
    } else {
      for (std::size_t i = 0; i < B; ++i) b.body_names.push_back("body_" + std::to_string(i));
    }
    auto tracks = [&](const char* key, const Array& a, std::size_t width) {
      numeric(key, a);
      expect_shape(key, a, {T_, B, width});
      std::vector<MatX> out(B, MatX(static_cast<Eigen::Index>(width), static_cast<Eigen::Index>(T_)));
      for (std::size_t t = 0; t < T_; ++t)
        for (std::size_t k = 0; k < B; ++k)
          for (std::size_t i = 0; i < width; ++i) {
            const double v = a.number((t * B + k) * width + i);
            if (!std::isfinite(v))
              throw InputError(value_loc(key, t) + " body " + b.body_names[k], std::isnan(v) ? "NaN is not allowed" : "infinite value");
            out[k](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(t)) = v;
          }
      return out;
    };
    for (MatX& m : tracks("body_pos_w", *pos, 3)) b.p_W_body.emplace_back(m);
    for (const MatX& m : tracks("body_quat_w", *quat, 4)) b.q_W_body.push_back(quaternions("body_quat_w", m));
    if (lin)
      for (MatX& m : tracks("body_lin_vel_w", *lin, 3)) b.v_W_body.emplace_back(m);
    if (ang)
      for (MatX& m : tracks("body_ang_vel_w", *ang, 3)) b.w_W_body.emplace_back(m);
  }

  const npz::NpzFile& f_;
  const ReferenceReadOptions& o_;
  std::size_t T_ = 0;
  const std::vector<std::string>* joint_names_ = nullptr;
};

}  // namespace

MatX joint_velocities(const MatX& q, double fps) {
  const Eigen::Index T = q.cols();
  MatX v = MatX::Zero(q.rows(), T);
  if (T < 2) return v;
  v.col(0) = (q.col(1) - q.col(0)) * fps;
  v.col(T - 1) = (q.col(T - 1) - q.col(T - 2)) * fps;
  for (Eigen::Index t = 1; t + 1 < T; ++t) v.col(t) = (q.col(t + 1) - q.col(t - 1)) * (0.5 * fps);
  return v;
}

std::string encode_reference_npz(const Reference& r, const NpzBodyArrays* bodies, const ReferenceNpzWriteOptions& o) {
  check_reference(r, "reference");
  const int T = r.num_frames();
  const std::size_t Ts = static_cast<std::size_t>(T);
  const std::size_t J = r.joint_names.size();
  const DType f = o.float32 ? DType::Float32 : DType::Float64;
  // Eigen matrices are column-major, so a rows x T matrix is already the (T, rows) C-order array.
  auto from_matrix = [&](const MatX& m) {
    return Array::from_doubles({static_cast<std::size_t>(m.cols()), static_cast<std::size_t>(m.rows())},
                               std::vector<double>(m.data(), m.data() + m.size()), f);
  };
  // Joint columns in the layout's order (bodies->joint_order), else the reference's.
  std::vector<std::string> joint_names = r.joint_names;
  MatX joint_pos = r.joint_pos;
  if (bodies && !bodies->joint_order.empty()) {
    RT_DEMAND(bodies->joint_order.size() == J, "NpzBodyArrays: joint_order must list every joint of the reference");
    for (std::size_t k = 0; k < J; ++k) {
      const auto it = std::find(r.joint_names.begin(), r.joint_names.end(), bodies->joint_order[k]);
      RT_DEMAND(it != r.joint_names.end(), "NpzBodyArrays: joint_order names a joint the reference does not have");
      joint_pos.row(static_cast<Eigen::Index>(k)) = r.joint_pos.row(it - r.joint_names.begin());
    }
    joint_names = bodies->joint_order;
  }
  std::vector<NamedArray> a;
  a.push_back({"fps", Array::from_doubles({1}, {r.fps}, DType::Float64), 0});
  a.push_back({"joint_names", Array::from_strings({J}, joint_names), 0});
  a.push_back({"joint_pos", from_matrix(joint_pos), 0});
  a.push_back({"joint_vel", from_matrix(joint_velocities(joint_pos, r.fps)), 0});
  a.push_back({"root_pos_w", from_matrix(r.root_pos_W), 0});
  MatX wxyz(4, T);
  for (int t = 0; t < T; ++t) {
    const Quat q = canonical_unit_quat(r.root_quat_W[static_cast<std::size_t>(t)]);
    wxyz.col(t) << q.w(), q.x(), q.y(), q.z();
  }
  a.push_back({"root_quat_w", from_matrix(wxyz), 0});
  if (r.has_contacts()) {
    std::vector<std::int64_t> flags(2 * Ts);
    for (std::size_t t = 0; t < Ts; ++t)
      for (std::size_t foot = 0; foot < 2; ++foot) flags[2 * t + foot] = r.contact[foot][t];
    a.push_back({"contacts", Array::from_ints({Ts, 2}, flags, DType::Bool), 0});
  }
  if (r.com_W.cols() > 0) a.push_back({"com_pos_w", from_matrix(r.com_W), 0});
  if (r.cop_W.cols() > 0) {
    a.push_back({"zmp_w", from_matrix(r.cop_W), 0});
    a.push_back({"cop_ref_w", from_matrix(r.cop_W), 0});
  }

  if (bodies && !bodies->empty()) {
    const NpzBodyArrays& b = *bodies;
    check_body_arrays(b, T);
    const std::size_t B = b.body_names.size();
    const auto& names = b.body_names;
    a.push_back({"body_names", Array::from_strings({B}, names), 0});
    a.push_back({"body_pos_w",
                 Array::from_doubles({Ts, B, 3}, per_frame_body(T, B, 3, names, "body_pos_w",
                                                                [&](std::size_t k, int t, int i) { return b.p_W_body[k](i, t); }),
                                     f),
                 0});
    a.push_back({"body_quat_w",
                 Array::from_doubles({Ts, B, 4}, per_frame_body(T, B, 4, names, "body_quat_w",
                                                                [&](std::size_t k, int t, int i) {
                                                                  const Quat q = canonical_unit_quat(
                                                                      b.q_W_body[k][static_cast<std::size_t>(t)]);
                                                                  const double wxyz_i[4] = {q.w(), q.x(), q.y(), q.z()};
                                                                  return wxyz_i[i];
                                                                }),
                                     f),
                 0});
    if (!b.v_W_body.empty())
      a.push_back({"body_lin_vel_w",
                   Array::from_doubles({Ts, B, 3}, per_frame_body(T, B, 3, names, "body_lin_vel_w",
                                                                  [&](std::size_t k, int t, int i) { return b.v_W_body[k](i, t); }),
                                       f),
                   0});
    if (!b.w_W_body.empty())
      a.push_back({"body_ang_vel_w",
                   Array::from_doubles({Ts, B, 3}, per_frame_body(T, B, 3, names, "body_ang_vel_w",
                                                                  [&](std::size_t k, int t, int i) { return b.w_W_body[k](i, t); }),
                                       f),
                   0});
  }
  npz::NpzWriteOptions w;
  w.compress = o.compress;
  return npz::encode_npz(a, w);
}

void write_reference_npz(const std::string& path, const Reference& reference, const NpzBodyArrays* bodies,
                         const ReferenceNpzWriteOptions& options) {
  write_file_atomic(path, encode_reference_npz(reference, bodies, options));
}

Reference decode_reference_npz(std::string_view bytes, const std::string& file, const ReferenceReadOptions& options,
                               NpzBodyArrays* bodies) {
  npz::NpzReadOptions limits;
  // Reference arrays deflate by a few times at most; 64x (at least 64 MiB) leaves a wide margin
  // while a decompression bomb (deflate allows ~1000x) is refused before it is inflated.
  limits.max_total_bytes = std::max<std::uint64_t>(64 * static_cast<std::uint64_t>(bytes.size()), std::uint64_t{64} << 20);
  const npz::NpzFile f = npz::decode_npz(bytes, file, limits);
  Reference r = NpzReferenceReader(f, options).read(bodies);
  check_reference(r, file);
  return r;
}

Reference read_reference_npz(const std::string& path, const ReferenceReadOptions& options, NpzBodyArrays* bodies) {
  const std::string bytes = read_file(path, options.max_file_bytes);
  return decode_reference_npz(bytes, base_name(path), options, bodies);
}

}  // namespace rt
