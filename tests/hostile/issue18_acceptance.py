#!/usr/bin/env python3
"""Issue 18's hostile cases (items 1-12) against the retarget binary, by hand:

    tests/hostile/issue18_acceptance.py [build/retarget]

Each case must end with the expected exit status (2 for bad input), a one-line error that names
where (file:line, file@offset, an option or a key), in under 5 s and under 1 GB peak RSS, and not
by a signal. Inputs are generated in a temporary folder; nothing is downloaded. Prints one line per
case and a total; exit 1 when any case fails. Items 6 and 7 (batch resume after kill -9, one lock
per output folder) are timing-dependent and covered by the ctest BatchRunner/BatchCli tests.
"""
import os
import struct
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "retarget"))
ROBOT = os.path.join(ROOT, "robots", "humanoid25")
CLIP = os.path.join(ROOT, "examples", "clips", "foot_lift.bvh")
MAX_S, MAX_MB = 5.0, 1024


def run(args, cwd, timeout=30):
    """Runs retarget; returns (status or -signal, stderr, seconds, peak RSS MB of that process)."""
    t0 = time.monotonic()
    p = subprocess.Popen([BIN] + args, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    timer = threading.Timer(timeout, p.kill)
    timer.start()
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    timer.cancel()
    p.returncode = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    return p.returncode, err.decode("utf-8", "replace"), time.monotonic() - t0, usage.ru_maxrss / 1024


# ---- generated inputs --------------------------------------------------------------------------

def bvh(frame_time="0.033333", frames=3):
    return ("HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
            "\tEnd Site\n\t{\n\t\tOFFSET 0 10 0\n\t}\n}\nMOTION\nFrames: %d\nFrame Time: %s\n" % (frames, frame_time)
            + "0 90 0 0 0 0\n" * frames)


def c3d(rate=100.0, used=None, scale=-0.1, frames=10, points=2, float_points=True, extra=()):
    """A minimal Intel C3D: header, POINT group (USED, RATE, SCALE, LABELS, FRAMES) and data.
    `used`: override POINT:USED as a float parameter value (item 4). `extra`: (group, name, type,
    dims, packed bytes) parameters."""
    groups = {"POINT": 1, "TRIAL": 2}
    params = []

    def param(group, name, typ, dims, data):
        params.append((groups[group], name, typ, dims, data))

    if used is None:
        param("POINT", "USED", 2, [], struct.pack("<h", points))
    else:
        param("POINT", "USED", 4, [], struct.pack("<f", used))
    param("POINT", "RATE", 4, [], struct.pack("<f", rate))
    param("POINT", "SCALE", 4, [], struct.pack("<f", scale))
    param("POINT", "FRAMES", 2, [], struct.pack("<h", frames))
    labels = ["LASI", "RASI", "LPSI", "RPSI", "LANK", "RANK"][:points]
    param("POINT", "LABELS", -1, [4, len(labels)], "".join(l.ljust(4) for l in labels).encode())
    for e in extra:
        param(*e)
    body = b""
    for name, gid in groups.items():
        nb = name.encode()
        body += struct.pack("<bb", len(nb), -gid) + nb + struct.pack("<h", 3) + b"\0"
    for gid, name, typ, dims, data in params:
        nb = name.encode()
        rec = struct.pack("<b", typ) + struct.pack("<b", len(dims)) + bytes(dims) + data + b"\0"
        body += struct.pack("<bb", len(nb), gid) + nb + struct.pack("<h", 2 + len(rec)) + rec
    body += struct.pack("<bb", 0, 0)
    nblocks = (4 + len(body) + 511) // 512
    param_section = (struct.pack("<BBBB", 1, 0x50, nblocks, 84) + body).ljust(512 * nblocks, b"\0")
    data_start = 2 + nblocks  # 1-based block number: header, then the parameter blocks
    header = struct.pack("<BB", 2, 0x50) + struct.pack("<hhhhh", points, 0, 1, frames, 10)
    header += struct.pack("<f", scale) + struct.pack("<hh", data_start, 0) + struct.pack("<f", rate)
    header = header.ljust(512, b"\0")
    data = b""
    for f in range(frames):
        for p in range(points):
            if float_points:
                data += struct.pack("<ffff", 100.0 * p, 50.0, 900.0 + f, 0.0)
            else:
                data += struct.pack("<hhhh", p, 5, 90, 0)
    return header + param_section + data


def urdf_chain(n, origin="0 0 0.01"):
    links = "".join('<link name="l%d"/>' % i for i in range(n + 1))
    joints = "".join('<joint name="j%d" type="fixed"><parent link="l%d"/><child link="l%d"/><origin xyz="%s"/></joint>'
                     % (i, i, i + 1, origin) for i in range(n))
    return '<robot name="chain">%s%s</robot>\n' % (links, joints)


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def main():
    if not os.access(BIN, os.X_OK):
        print("no retarget binary at", BIN)
        return 2
    d = tempfile.mkdtemp(prefix="issue18_")
    rob = ["--robot", ROBOT]
    quick = ["--no-refine"]
    # A valid reference to validate (CSV + meta.json), converted once.
    rc, err, _, _ = run(["convert", CLIP] + rob + quick + ["-o", "ref.csv"], d, timeout=120)
    if rc != 0:
        print("could not make the reference:", err)
        return 2
    meta = open(os.path.join(d, "ref.meta.json")).read()
    csv = open(os.path.join(d, "ref.csv")).read()

    def with_meta(name, new_meta):
        write(os.path.join(d, name + ".csv"), csv)
        write(os.path.join(d, name + ".meta.json"), new_meta)
        return name + ".csv"

    fps_at = meta.index('"fps":')
    fps_end = min(i for i in (meta.find(",", fps_at), meta.find("\n", fps_at)) if i >= 0)
    # robot.yaml / URDF variants in their own folders (the config's URDF path is relative).
    h25 = open(os.path.join(ROBOT, "robot.yaml")).read()
    h25_urdf = open(os.path.join(ROBOT, "humanoid25.urdf")).read()

    def robot_variant(name, yaml=h25, urdf=h25_urdf):
        write(os.path.join(d, name, "robot.yaml"), yaml)
        write(os.path.join(d, name, "humanoid25.urdf"), urdf)
        return os.path.join(d, name)

    import re
    first_offset = re.search(r"offset: \[[^\]]*\]", h25)
    first_origin = re.search(r'<origin xyz="[^"]*"', h25_urdf)
    write(os.path.join(d, "ft1000.bvh"), bvh("1000"))
    write(os.path.join(d, "ft100.bvh"), bvh("100", frames=50))
    write(os.path.join(d, "rate.c3d"), c3d(rate=0.001))
    write(os.path.join(d, "rate30.c3d"), c3d(rate=1e-30))
    for tag, v in (("nan", float("nan")), ("neg", -1.0), ("1e10", 1e10)):
        write(os.path.join(d, "used_%s.c3d" % tag), c3d(used=v))
    write(os.path.join(d, "used_1e8.c3d"), c3d(used=1e8, frames=0))
    write(os.path.join(d, "intscale.c3d"), c3d(scale=0.1, float_points=True))
    write(os.path.join(d, "trial_inf.c3d"),
          c3d(extra=[("TRIAL", "CAMERA_RATE", 4, [], struct.pack("<f", float("inf")))]))
    # URDFs of their own, loaded through a robot.yaml that names them (humanoid25's, URDF replaced).
    def urdf_robot(name, urdf):
        write(os.path.join(d, name, "robot.yaml"), h25.replace("urdf: humanoid25.urdf", "urdf: robot.urdf"))
        write(os.path.join(d, name, "robot.urdf"), urdf)
        return os.path.join(d, name)

    chain20k = urdf_robot("chain20k", urdf_chain(20000))
    chain10k = urdf_robot("chain10k", urdf_chain(10000))
    attrs = urdf_robot("attrs", '<robot name="r"><link name="a" ' + " ".join('x%d="1"' % i for i in range(200000)) + "/></robot>\n")
    utf16 = urdf_robot("utf16", '<?xml version="1.0" encoding="UTF-16"?><robot name="r"><link name="a"/></robot>'.encode("utf-16"))
    os.mkfifo(os.path.join(d, "clip.bvh"))
    os.mkfifo(os.path.join(d, "m.yaml"))
    os.mkfifo(os.path.join(d, "fifo.csv"))
    os.mkfifo(os.path.join(d, "fifo.npz"))
    os.mkfifo(os.path.join(d, "profile.yaml"))
    os.makedirs(os.path.join(d, "afolder"), exist_ok=True)
    write(os.path.join(d, "in", "a.bvh"), open(CLIP).read())
    write(os.path.join(d, "in", "m_profile.yaml"), "clips:\n  - {path: a.bvh, profile: /etc/passwd}\n")
    write(os.path.join(d, "in", "m_fifo_profile.yaml"), "clips:\n  - {path: a.bvh, profile: %s}\n" % os.path.join(d, "profile.yaml"))
    write(os.path.join(d, "in", "m_dup.yaml"), "clips:\n  - a.bvh\nclips:\n  - a.bvh\n")
    # Item 11: an OBJ with one 10M-vertex polygon, a 2 GB sparse STL (robot folders of their own).
    obj_robot = robot_variant("obj_robot")
    with open(os.path.join(obj_robot, "big.obj"), "w") as f:  # in chunks: a child's peak RSS counts this process's
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf")
        for _ in range(100):
            f.write(" 1 2 3" * 33_334)
        f.write("\n")
    write(os.path.join(obj_robot, "humanoid25.urdf"), h25_urdf.replace("</robot>", '<link name="extra"><collision><geometry><mesh filename="big.obj"/></geometry></collision></link>'
                                                                     '<joint name="xj" type="fixed"><parent link="pelvis"/><child link="extra"/></joint></robot>'))
    stl_robot = robot_variant("stl_robot")
    with open(os.path.join(stl_robot, "big.stl"), "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", 40_000_000))
        f.truncate(2 << 30)
    write(os.path.join(stl_robot, "humanoid25.urdf"), h25_urdf.replace("</robot>", '<link name="extra"><collision><geometry><mesh filename="big.stl"/></geometry></collision></link>'
                                                                     '<joint name="xj" type="fixed"><parent link="pelvis"/><child link="extra"/></joint></robot>'))

    cases = [
        # item 1
        *[("1 validate --fps %s" % v, ["validate", "ref.csv", "--fps", v] + rob, 2, "--fps") for v in ("1e300", "1e15", "1e11", "1e10", "1e9")],
        # item 2
        ("2 meta fps 0.001", ["validate", with_meta("slow", meta[:fps_at] + '"fps": 0.001' + meta[fps_end:])] + rob, 2, "fps"),
        ("2 meta duplicate fps", ["validate", with_meta("dup", meta[:fps_at] + '"fps": 0.001, ' + meta[fps_at:])] + rob, 2, "duplicate key"),
        ("2 validate --fps 0.01", ["validate", "ref.csv", "--fps", "0.01"] + rob, 2, "--fps"),
        # item 3
        ("3 BVH Frame Time 1000", ["convert", "ft1000.bvh"] + rob + quick, 2, "ft1000.bvh"),
        ("3 BVH Frame Time 100", ["convert", "ft100.bvh"] + rob + quick, 2, "ft100.bvh"),
        ("3 --source-fps 1e-6", ["convert", CLIP, "--source-fps", "1e-6"] + rob, 2, "--source-fps"),
        ("3 C3D POINT:RATE 0.001", ["convert", "rate.c3d"] + rob + quick, 2, "rate.c3d"),
        # item 4
        *[("4 C3D POINT:USED %s" % t, ["convert", "used_%s.c3d" % t] + rob + quick, 2, "used_%s.c3d" % t) for t in ("nan", "neg", "1e10", "1e8")],
        ("4 C3D float data, POINT:SCALE > 0", ["inspect", "intscale.c3d"], None, None),
        # item 5
        ("5 URDF chain of 20000 links", ["inspect", chain20k], 2, "robot.urdf"),
        ("5 URDF chain of 10000 links", ["inspect", chain10k], 2, "robot.urdf"),
        # item 8
        ("8 convert FIFO clip", ["convert", "clip.bvh"] + rob, 2, "FIFO"),
        ("8 convert FIFO profile", ["convert", CLIP, "--skeleton-profile", "profile.yaml"] + rob, 2, "FIFO"),
        ("8 batch FIFO manifest", ["batch", "m.yaml", "-o", "out_fifo"] + rob, 2, "FIFO"),
        ("8 validate FIFO CSV", ["validate", "fifo.csv", "--fps", "30"] + rob, 2, "FIFO"),
        ("8 validate FIFO NPZ", ["validate", "fifo.npz"] + rob, 2, "FIFO"),
        ("8 convert /dev/zero", ["convert", "/dev/zero"] + rob, 2, "character device"),
        ("8 inspect FIFO", ["inspect", "clip.bvh"], 2, "FIFO"),
        ("8 inspect folder", ["inspect", "afolder"], 2, "afolder"),
        # item 9
        ("9 manifest profile outside root", ["batch", "in/m_profile.yaml", "-o", "out9"] + rob, 2, "outside"),
        # item 10
        *[("10 --passes %s alone" % p, ["convert", CLIP, "--passes", p] + rob, 2, "--passes") for p in ("refine", "ik", "ground", "resample", "com-replan")],
        ("10 com-replan{period=1e-9}", ["convert", CLIP, "--passes", "scale,label-contacts,ik,com-replan{period=1e-9},resample"] + rob, 2, "period"),
        # item 11
        ("11 URDF element with 200k attributes", ["inspect", attrs], 2, "robot.urdf"),
        ("11 OBJ polygon of 10M vertices", ["inspect", obj_robot], 2, "big.obj"),
        ("11 2 GB sparse STL", ["inspect", stl_robot], 2, "big.stl"),
        # item 12
        ("12 robot.yaml offset 1e300", ["inspect", robot_variant("off1e300", yaml=h25[:first_offset.start()] + "offset: [1e300, 0, 0]" + h25[first_offset.end():])], 2, "robot.yaml"),
        ("12 URDF joint origin 1e300", ["inspect", robot_variant("orig1e300", urdf=h25_urdf[:first_origin.start()] + '<origin xyz="1e300 0 0"' + h25_urdf[first_origin.end():])], 2, "humanoid25.urdf"),
        ("12 robot.yaml duplicate key", ["inspect", robot_variant("dupyaml", yaml=h25 + "\nname: again\n")], 2, "duplicate key"),
        ("12 batch manifest duplicate key", ["batch", "in/m_dup.yaml", "-o", "out12"] + rob, 2, "duplicate key"),
        ("12 UTF-16 URDF", ["inspect", utf16], 2, "robot.urdf"),
        ("12 C3D rate 1e-30", ["convert", "rate30.c3d"] + rob + quick, 2, "rate30.c3d"),
        ("12 C3D TRIAL:CAMERA_RATE inf", ["inspect", "trial_inf.c3d"], None, None),
        ("12 --fps inf", ["convert", CLIP, "--fps", "inf"] + rob, 2, "--fps"),
        ("12 cannot open: errno text", ["convert", "missing.bvh"] + rob, 2, "No such file or directory"),
        # item 3 of the follow-up: usage errors are one line
        ("usage error is one line", ["convert", CLIP, "--fps"] + rob, 2, "--fps"),
    ]
    failed = 0
    peak = 0.0
    for name, args, want_rc, says in cases:
        rc, err, dt, rss = run(args, d)
        peak = max(peak, rss)
        lines = [l for l in err.splitlines() if l.startswith("error:") or l.startswith("internal error")]
        problems = []
        if rc < 0:
            problems.append("killed by signal %d" % -rc)
        if want_rc is not None and rc != want_rc:
            problems.append("exit %s, expected %d" % (rc, want_rc))
        if want_rc is None and rc not in (0, 1, 2):
            problems.append("exit %s" % rc)
        if want_rc == 2 and len(lines) != 1:
            problems.append("%d error lines" % len(lines))
        if says and says not in err:
            problems.append("error does not mention %r" % says)
        if dt > MAX_S:
            problems.append("%.1f s" % dt)
        if rss > MAX_MB:
            problems.append("%.0f MB" % rss)
        failed += bool(problems)
        last = lines[-1] if lines else (err.strip().splitlines() or [""])[-1]
        print("%-38s exit %-3s %5.2f s %5.0f MB  %s | %s" % (name, rc, dt, rss, "FAIL " + "; ".join(problems) if problems else "ok", last[:140]))
    print("%d cases, %d failed; largest peak RSS %.0f MB; inputs in %s" % (len(cases), failed, peak, d))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
