#pragma once
/// A Reference as an .npz with BeyondMimic-style keys (design.md §5), loadable by numpy.load.
/// T = frames, J = joints, B = bodies. Floats are '<f8' unless written with float32 = true ('<f4').
///
///   key             dtype   shape      content
///   fps             <f8     (1,)       [Hz] frame rate; frame k at t = k / fps               (required)
///   joint_names     <U<n>   (J,)       joint names, column order of joint_pos                  (*)
///   joint_pos       <f8     (T, J)     [rad | m] joint positions                               (required)
///   joint_vel       <f8     (T, J)     [rad/s | m/s] central differences of joint_pos
///                                      ((q[k+1] - q[k-1]) fps / 2; one-sided at the ends; 0 if T = 1)
///   root_pos_w      <f8     (T, 3)     [m] root link origin in W                              (**)
///   root_quat_w     <f8     (T, 4)     root link orientation, **w x y z**                      (**)
///   contacts        |b1     (T, 2)     stance flags, column 0 left foot, 1 right foot (when known)
///   com_pos_w       <f8     (T, 3)     [m] planned COM (when present)
///   zmp_w           <f8     (T, 2)     [m] planned ZMP x y, the COP to realise (when present)
///   cop_ref_w       <f8     (T, 2)     [m] the same as zmp_w (design.md's name); read when zmp_w is absent
///   body_names      <U<n>   (B,)       link names (when body arrays are given)
///   body_pos_w      <f8     (T, B, 3)  [m] link origins in W
///   body_quat_w     <f8     (T, B, 4)  link orientations, **w x y z**
///   body_lin_vel_w  <f8     (T, B, 3)  [m/s] (when given)
///   body_ang_vel_w  <f8     (T, B, 3)  [rad/s] (when given)
///
/// Reading: `fps` and `joint_pos` are required. (*) `joint_names` may be absent (plain BeyondMimic
/// files have none) only when the caller states the order (ReferenceReadOptions::npz_joint_order,
/// `validate --joint-order`); its count must match. The robot's own order is never assumed. (**) The root pose is `root_pos_w` + `root_quat_w` (both or neither); without them
/// body 0 of `body_pos_w` + `body_quat_w` is taken as the root (body 0 is the articulation root in
/// Isaac Lab / BeyondMimic exports). Optional `time_s` or `time` (T,) time stamps are checked
/// (strictly increasing, uniform 1/fps). Numeric keys may have any numeric dtype of npy_array.hpp;
/// contacts must be 0/1. Unknown keys are ignored. The arrays may inflate to at most 64x the file
/// size (at least 64 MiB), which real references never approach and decompression bombs exceed. Every shape is checked against T, J, B; every
/// value must be finite; root quaternions unit within the tolerance (normalised as in the CSV).
/// Errors: InputError "<file>@0x<offset> [<key>.npy]: ..." or, for values,
/// "<file> [<key>] frame <k> joint <name>: ...".

#include <string>
#include <string_view>

#include "retarget/core/types.hpp"
#include "retarget/reference/npz_body_arrays.hpp"
#include "retarget/reference/reference.hpp"
#include "retarget/reference/reference_io.hpp"

namespace rt {

struct ReferenceNpzWriteOptions {
  bool compress = true;  ///< deflate entries (numpy.savez_compressed); false = stored
  bool float32 = false;  ///< '<f4' instead of '<f8' for float arrays (fps stays '<f8'); halves the size
};

/// Joint velocities J x T [rad/s] by central differences (one-sided at the ends, 0 for T = 1).
MatX joint_velocities(const MatX& joint_pos, double fps);

/// The .npz bytes of `reference` (after check_reference) plus `bodies` when given (InternalError
/// when their sizes disagree with the reference; InputError on non-finite values). The joint
/// columns follow bodies->joint_order when it is given (npz_layout.hpp), else the reference.
std::string encode_reference_npz(const Reference& reference, const NpzBodyArrays* bodies = nullptr,
                                 const ReferenceNpzWriteOptions& options = {});

/// Writes encode_reference_npz atomically.
void write_reference_npz(const std::string& path, const Reference& reference, const NpzBodyArrays* bodies = nullptr,
                         const ReferenceNpzWriteOptions& options = {});

/// Parses .npz bytes into a Reference (see the key table for what is required). Uses
/// options.npz_joint_order only when the file has no joint_names, and options.quat_norm_tolerance;
/// robot and fps checks against `options` are read_reference's job. `bodies`, when given, receives
/// the body arrays (cleared when the file has none).
Reference decode_reference_npz(std::string_view bytes, const std::string& file, const ReferenceReadOptions& options = {},
                               NpzBodyArrays* bodies = nullptr);

/// Reads an .npz reference from disk (options.max_file_bytes applies).
Reference read_reference_npz(const std::string& path, const ReferenceReadOptions& options = {},
                             NpzBodyArrays* bodies = nullptr);

}  // namespace rt
