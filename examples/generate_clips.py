#!/usr/bin/env python3
"""Writes the project's example clips (examples/clips/*.bvh): small, synthetic human motions
authored by the project, used by the README's main command, tests and golden files.

  foot_lift.bvh   stand, shift the weight towards the left foot, lift the right foot for
                  t in [1.0, 2.0) s, put it down, stand (the paper's Fig. 7 motion, done the way a
                  person does it: with a modest weight shift of their own)
  slow_steps.bvh  stand, then four slow steps (step-to gait: the right foot steps 0.18 m forward,
                  the left joins it, twice), the weight shifted over the stance foot before every
                  lift, then stand
  stand.bvh       3 s of quiet standing

Skeleton: a 19-joint humanoid with Mixamo/PyMO-style names (Hips, LeftUpLeg, ...), centimetres,
Y up, facing +Z (left = +X). Channels: root Xposition Yposition Zposition Zrotation Xrotation
Yrotation; others Zrotation Xrotation Yrotation (rotations intrinsic, in that order).
Legs are posed by an analytic two-link IK from a pelvis trajectory and foot placements, so the
stance feet do not slide. Run: python3 examples/generate_clips.py (writes next to this script).
"""

import math
import os

FPS = 60
# Rest-pose offsets [cm].
HIP_X, HIP_Y = 9.0, -6.0
THIGH, SHANK = 42.0, 41.0
ANKLE_H = 6.0          # ankle above the sole
TOE = (0.0, -6.0, 13.0)
PELVIS_H = ANKLE_H + SHANK + THIGH - HIP_Y   # 95 cm with straight legs

JOINTS = [
    # name, parent, offset
    ("Hips", None, (0, 0, 0)),
    ("LeftUpLeg", "Hips", (HIP_X, HIP_Y, 0)),
    ("LeftLeg", "LeftUpLeg", (0, -THIGH, 0)),
    ("LeftFoot", "LeftLeg", (0, -SHANK, 0)),
    ("LeftToeBase", "LeftFoot", TOE),
    ("RightUpLeg", "Hips", (-HIP_X, HIP_Y, 0)),
    ("RightLeg", "RightUpLeg", (0, -THIGH, 0)),
    ("RightFoot", "RightLeg", (0, -SHANK, 0)),
    ("RightToeBase", "RightFoot", TOE),
    ("Spine", "Hips", (0, 10, 0)),
    ("Spine1", "Spine", (0, 15, 0)),
    ("Neck", "Spine1", (0, 20, 0)),
    ("Head", "Neck", (0, 8, 0)),
    ("LeftShoulder", "Spine1", (4, 17, 0)),
    ("LeftArm", "LeftShoulder", (13, 0, 0)),
    ("LeftForeArm", "LeftArm", (28, 0, 0)),
    ("LeftHand", "LeftForeArm", (25, 0, 0)),
    ("RightShoulder", "Spine1", (-4, 17, 0)),
    ("RightArm", "RightShoulder", (-13, 0, 0)),
    ("RightForeArm", "RightArm", (-28, 0, 0)),
    ("RightHand", "RightForeArm", (-25, 0, 0)),
]
END_SITES = {"LeftToeBase": (0, 0, 5), "RightToeBase": (0, 0, 5), "Head": (0, 16, 0),
             "LeftHand": (8, 0, 0), "RightHand": (-8, 0, 0)}


def smooth(x):
    """0 -> 1 with zero slope at both ends (quintic smoothstep)."""
    x = min(1.0, max(0.0, x))
    return x * x * x * (10 - 15 * x + 6 * x * x)


def ramp(t, t0, t1):
    return smooth((t - t0) / (t1 - t0))


def leg_ik(hip, ankle):
    """Hip roll (about forward Z), hip pitch (about X), knee (about X) placing the ankle.

    Positions in the Y-up, Z-forward frame. R_hip = Rz(roll) Rx(pitch); the leg hangs along -Y.
    """
    dx, dy, dz = (ankle[i] - hip[i] for i in range(3))
    roll = math.atan2(dx, -dy)                      # tilt of the leg plane sideways
    down = math.hypot(dx, dy)                       # length in the rolled plane, downwards
    L = math.sqrt(down * down + dz * dz)
    L = min(L, THIGH + SHANK - 1e-6)
    cos_knee = (THIGH ** 2 + SHANK ** 2 - L ** 2) / (2 * THIGH * SHANK)
    knee = math.pi - math.acos(max(-1.0, min(1.0, cos_knee)))   # flexion > 0
    # Angle of the hip->ankle line ahead of straight down (forward = -Rx rotation).
    line = math.atan2(dz, down)
    inner = math.asin(max(-1.0, min(1.0, SHANK * math.sin(knee) / L)))
    pitch = -(line + inner)                          # thigh forward of the line by `inner`
    return roll, pitch, knee


def frame_channels(pelvis, feet, spine_lean=0.0, arm_swing=0.0):
    """Channel values for one frame. pelvis = (x, y, z) [cm]; feet = {side: (x, y, z) ankle}."""
    vals = {}
    vals["Hips"] = [pelvis[0], pelvis[1], pelvis[2], 0.0, 0.0, 0.0]
    for side, sgn in (("Left", 1), ("Right", -1)):
        hip = (pelvis[0] + sgn * HIP_X, pelvis[1] + HIP_Y, pelvis[2])
        roll, pitch, knee = leg_ik(hip, feet[side])
        vals[side + "UpLeg"] = [math.degrees(roll), math.degrees(pitch), 0.0]
        vals[side + "Leg"] = [0.0, math.degrees(knee), 0.0]
        # Keep the foot level: undo the leg's pitch and roll at the ankle.
        vals[side + "Foot"] = [-math.degrees(roll), -math.degrees(pitch + knee), 0.0]
        vals[side + "ToeBase"] = [0.0, 0.0, 0.0]
        # Arms hang down (rotate the +-X arm about Z by -+80 deg), slight elbow bend.
        vals[side + "Shoulder"] = [0.0, 0.0, 0.0]
        vals[side + "Arm"] = [-sgn * 80.0, sgn * arm_swing, 0.0]
        vals[side + "ForeArm"] = [0.0, 0.0, -sgn * 15.0]
        vals[side + "Hand"] = [0.0, 0.0, 0.0]
    vals["Spine"] = [0.0, spine_lean, 0.0]
    for name in ("Spine1", "Neck", "Head"):
        vals[name] = [0.0, 0.0, 0.0]
    return vals


def stand_height():
    return PELVIS_H - 5.0   # knees bent a little, so the trailing leg never straightens during a step


def foot_lift(t):
    shift = 5.0 * ramp(t, 0.3, 0.9) * (1 - ramp(t, 2.2, 2.8))      # towards the left foot (+X)
    lift = 10.0 * ramp(t, 1.0, 1.3) * (1 - ramp(t, 1.7, 2.0))      # right foot height [cm]
    pelvis = (shift, stand_height(), 0.0)
    feet = {"Left": (HIP_X, ANKLE_H, 0.0), "Right": (-HIP_X, ANKLE_H + lift, 2.0 * lift / 10.0)}
    return frame_channels(pelvis, feet)


def slow_steps_plan():
    """Phases (t0, t1, pelvis_end (x, z), swing foot or None, swing target z). The pelvis moves
    smoothly from where the previous phase left it; feet only move while swinging."""
    step, t = 18.0, 1.0
    feet_z = {"Left": 0.0, "Right": 0.0}
    feet_x = {"Left": HIP_X, "Right": -HIP_X}
    phases = []
    for swing in ["Right", "Left", "Right", "Left"]:
        stance = "Left" if swing == "Right" else "Right"
        over_stance = (0.9 * feet_x[stance], feet_z[stance])
        phases.append((t, t + 1.2, over_stance, None, None))                     # weight shift
        target = feet_z[swing] + step if feet_z[swing] <= feet_z[stance] else feet_z[stance]
        target = max(target, feet_z[stance])
        phases.append((t + 1.2, t + 2.4, over_stance, swing, target))           # single support
        feet_z[swing] = target
        t += 2.4
    phases.append((t, t + 1.2, (0.0, 0.5 * (feet_z["Left"] + feet_z["Right"])), None, None))
    return phases, t + 2.2


def slow_steps(t, phases):
    pelvis = (0.0, 0.0)
    feet_z = {"Left": 0.0, "Right": 0.0}
    lift = {"Left": 0.0, "Right": 0.0}
    for t0, t1, pelvis_end, swing, target in phases:
        if t < t0:
            break
        s = ramp(t, t0, t1)
        pelvis = tuple(pelvis[i] + s * (pelvis_end[i] - pelvis[i]) for i in range(2))
        if swing is not None:
            start = feet_z[swing]
            feet_z[swing] = start + s * (target - start)
            lift[swing] = 8.0 * math.sin(math.pi * s) if t < t1 else 0.0
    ankles = {"Left": (HIP_X, ANKLE_H + lift["Left"], feet_z["Left"]),
              "Right": (-HIP_X, ANKLE_H + lift["Right"], feet_z["Right"])}
    return frame_channels((pelvis[0], stand_height(), pelvis[1]), ankles)


def stand(t):
    return frame_channels((0.0, stand_height(), 0.0), {"Left": (HIP_X, ANKLE_H, 0.0), "Right": (-HIP_X, ANKLE_H, 0.0)})


def write_bvh(path, frames):
    children = {}
    for name, parent, _ in JOINTS:
        children.setdefault(parent, []).append(name)
    offsets = {name: off for name, _, off in JOINTS}
    lines = ["HIERARCHY"]

    def emit(name, depth):
        pad = "  " * depth
        lines.append(f"{pad}{'ROOT' if depth == 0 else 'JOINT'} {name}")
        lines.append(pad + "{")
        lines.append(pad + "  OFFSET %.4f %.4f %.4f" % offsets[name])
        if depth == 0:
            lines.append(pad + "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation")
        else:
            lines.append(pad + "  CHANNELS 3 Zrotation Xrotation Yrotation")
        for c in children.get(name, []):
            emit(c, depth + 1)
        if name in END_SITES:
            lines.append(pad + "  End Site")
            lines.append(pad + "  {")
            lines.append(pad + "    OFFSET %.4f %.4f %.4f" % END_SITES[name])
            lines.append(pad + "  }")
        lines.append(pad + "}")

    emit("Hips", 0)
    order = []

    def collect(name):
        order.append(name)
        for c in children.get(name, []):
            collect(c)

    collect("Hips")
    lines.append("MOTION")
    lines.append(f"Frames: {len(frames)}")
    lines.append("Frame Time: %.7f" % (1.0 / FPS))
    for vals in frames:
        lines.append(" ".join("%.4f" % v for name in order for v in vals[name]))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "clips")
    os.makedirs(here, exist_ok=True)
    write_bvh(os.path.join(here, "foot_lift.bvh"), [foot_lift(k / FPS) for k in range(int(3.5 * FPS))])
    plan, end = slow_steps_plan()
    write_bvh(os.path.join(here, "slow_steps.bvh"), [slow_steps(k / FPS, plan) for k in range(int(end * FPS))])
    write_bvh(os.path.join(here, "stand.bvh"), [stand(k / FPS) for k in range(3 * FPS)])


if __name__ == "__main__":
    main()
