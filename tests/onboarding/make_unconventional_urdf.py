#!/usr/bin/env python3
"""Rewrites a real humanoid URDF the way unconventional robots are written, without changing the
robot (issue 17: onboarding robots we do not have):

  make_unconventional_urdf.py SRC.urdf OUT_DIR PKG [--package-root DIR] [--fingers N]

writes OUT_DIR/PKG/<name>_unconventional.urdf and OUT_DIR/PKG/meshes/*.dae with
  - the root link's frame turned 180 deg about z (+x backwards, +y to the robot's right);
  - DH-style link frames: every moving link's frame turned so that its joint axis is its z axis,
    then twisted 0.5 rad about it (so no link frame has z up or x forward);
  - every mesh as a Y_UP COLLADA file in millimetres, referenced as package:///PKG/meshes/...
    (empty authority, as example-robot-data writes them);
  - right-side links referencing the left mesh mirrored (scale="1 -1 1") wherever the right STL is
    the left one mirrored in y;
  - with --fingers N, N three-joint fingers on each hand link (the last link of each arm with a
    "hand" in its name), so the arms end in many small chains.
Kinematics, masses and geometry are unchanged: configs guessed for the result should retarget and
balance the same as for the source. STL meshes only; package:// URIs resolve under --package-root.
"""
import argparse
import math
import os
import struct
import xml.etree.ElementTree as ET

import numpy as np


def rpy_to_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def matrix_to_rpy(R):
    p = math.asin(max(-1.0, min(1.0, -R[2, 0])))
    if abs(math.cos(p)) > 1e-9:
        return math.atan2(R[2, 1], R[2, 2]), p, math.atan2(R[1, 0], R[0, 0])
    return math.atan2(-R[1, 2], R[1, 1]), p, 0.0


def axis_angle(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def z_onto(axis):
    """A rotation taking +z onto the unit vector `axis`."""
    z = np.array([0.0, 0.0, 1.0])
    c = np.cross(z, axis)
    if np.linalg.norm(c) < 1e-9:
        return np.eye(3) if axis[2] > 0 else axis_angle([1, 0, 0], math.pi)
    return axis_angle(c, math.acos(float(np.clip(axis @ z, -1, 1))))


def read_origin(el):
    o = el.find('origin')
    xyz, R = np.zeros(3), np.eye(3)
    if o is not None:
        if o.get('xyz'):
            xyz = np.array([float(v) for v in o.get('xyz').split()])
        if o.get('rpy'):
            R = rpy_to_matrix(*[float(v) for v in o.get('rpy').split()])
    return xyz, R


def write_origin(el, xyz, R):
    o = el.find('origin')
    if o is None:
        o = ET.Element('origin')
        el.insert(0, o)
    o.set('xyz', ' '.join('%.9g' % v for v in xyz))
    o.set('rpy', ' '.join('%.12g' % v for v in matrix_to_rpy(R)))


def read_stl(path):
    """Triangles (n, 3, 3) of an ASCII or binary STL."""
    data = open(path, 'rb').read()
    if data[:5] == b'solid' and b'facet' in data[:300]:
        v = [[float(c) for c in line.split()[1:4]] for line in data.decode(errors='ignore').splitlines()
             if line.split()[:1] == ['vertex']]
        return np.array(v).reshape(-1, 3, 3)
    n = struct.unpack('<I', data[80:84])[0]
    rec = np.frombuffer(data[84:84 + 50 * n], dtype=np.dtype([('n', '<3f4'), ('v', '<9f4'), ('a', '<u2')]))
    return rec['v'].astype(float).reshape(-1, 3, 3)


def write_collada_y_up_mm(triangles, path):
    # Y_UP: an importer turns the file's +y into +z (a +90 deg turn about x), so (x, y, z) is stored
    # as (x, z, -y); millimetres, declared in <unit>.
    v = triangles.reshape(-1, 3) * 1000.0
    v = np.stack([v[:, 0], v[:, 2], -v[:, 1]], axis=1)
    n = len(v)
    positions = ' '.join('%.6f' % c for c in v.ravel())
    indices = ' '.join(str(i) for i in range(n))
    with open(path, 'w') as f:
        f.write(f'''<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="mesh" name="mesh"><mesh>
      <source id="mesh-pos"><float_array id="mesh-pos-array" count="{3 * n}">{positions}</float_array>
        <technique_common><accessor source="#mesh-pos-array" count="{n}" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="mesh-vtx"><input semantic="POSITION" source="#mesh-pos"/></vertices>
      <triangles count="{n // 3}"><input semantic="VERTEX" source="#mesh-vtx" offset="0"/><p>{indices}</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n" name="n">
    <instance_geometry url="#mesh"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
''')


def add_fingers(robot, count):
    links = {l.get('name') for l in robot.findall('link')}
    parents = {j.find('parent').get('link') for j in robot.findall('joint')}
    hands = sorted(n for n in links if 'hand' in n.lower() and n not in parents)
    for hand in hands:
        for i in range(count):
            parent = hand
            for k in range(3):
                name = f'{hand}_finger{i}_{k}'
                link = ET.SubElement(robot, 'link', name=name)
                inertial = ET.SubElement(link, 'inertial')
                ET.SubElement(inertial, 'origin', xyz='0.01 0 0', rpy='0 0 0')
                ET.SubElement(inertial, 'mass', value='0.01')
                ET.SubElement(inertial, 'inertia', ixx='1e-6', ixy='0', ixz='0', iyy='1e-6', iyz='0', izz='1e-6')
                collision = ET.SubElement(link, 'collision')
                ET.SubElement(collision, 'origin', xyz='0.01 0 0', rpy='0 0 0')
                ET.SubElement(ET.SubElement(collision, 'geometry'), 'box', size='0.02 0.01 0.01')
                joint = ET.SubElement(robot, 'joint', name=name + '_joint', type='revolute')
                ET.SubElement(joint, 'origin', xyz=f'0.02 {0.01 * (i - (count - 1) / 2):g} 0' if k == 0 else '0.02 0 0', rpy='0 0 0')
                ET.SubElement(joint, 'parent', link=parent)
                ET.SubElement(joint, 'child', link=name)
                ET.SubElement(joint, 'axis', xyz='0 0 1')
                ET.SubElement(joint, 'limit', lower='0', upper='1.5', effort='2', velocity='5')
                parent = name
    return len(hands) * count * 3


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('urdf')
    ap.add_argument('out_dir')
    ap.add_argument('package')
    ap.add_argument('--package-root', default='', help='folder that package://NAME/... URIs resolve under')
    ap.add_argument('--fingers', type=int, default=0)
    a = ap.parse_args()
    src_dir = os.path.dirname(os.path.abspath(a.urdf))
    mesh_dir = os.path.join(a.out_dir, a.package, 'meshes')
    os.makedirs(mesh_dir, exist_ok=True)
    tree = ET.parse(a.urdf)
    robot = tree.getroot()
    fingers = add_fingers(robot, a.fingers) if a.fingers > 0 else 0
    links = {l.get('name'): l for l in robot.findall('link')}
    joints = robot.findall('joint')
    children = {j.find('child').get('link') for j in joints}
    root = next(n for n in links if n not in children)

    # Q[link]: the new frame's axes in the old frame.
    Q = {n: np.eye(3) for n in links}
    Q[root] = axis_angle([0, 0, 1], math.pi)
    for j in joints:
        if j.get('type') in ('revolute', 'continuous', 'prismatic'):
            axis = np.array([float(v) for v in j.find('axis').get('xyz').split()])
            axis /= np.linalg.norm(axis)
            Q[j.find('child').get('link')] = axis_angle(axis, 0.5) @ z_onto(axis)
    for j in joints:
        parent, child = j.find('parent').get('link'), j.find('child').get('link')
        p, R = read_origin(j)
        write_origin(j, Q[parent].T @ p, Q[parent].T @ R @ Q[child])
        axis = j.find('axis')
        if axis is not None:
            axis.set('xyz', ' '.join('%.12g' % v for v in Q[child].T @ np.array([float(v) for v in axis.get('xyz').split()])))

    def resolve(uri):
        if uri.startswith('package://'):
            return os.path.join(a.package_root, uri[len('package://'):])
        return uri if os.path.isabs(uri) else os.path.join(src_dir, uri)

    written = {}

    def collada_for(uri):
        if uri not in written:
            name = os.path.splitext(os.path.basename(uri))[0] + '.dae'
            write_collada_y_up_mm(read_stl(resolve(uri)), os.path.join(mesh_dir, name))
            written[uri] = name
        return written[uri]

    def mirrors(right_uri, left_uri):
        if not os.path.exists(resolve(left_uri)):
            return False
        r = read_stl(resolve(right_uri)).reshape(-1, 3)
        l = read_stl(resolve(left_uri)).reshape(-1, 3) * np.array([1, -1, 1])
        return np.abs(r.min(0) - l.min(0)).max() < 1e-3 and np.abs(r.max(0) - l.max(0)).max() < 1e-3

    mirrored = 0
    for name, link in links.items():
        for el in link.findall('inertial') + link.findall('visual') + link.findall('collision'):
            p, R = read_origin(el)
            write_origin(el, Q[name].T @ p, Q[name].T @ R)
            mesh = el.find('geometry/mesh')
            if mesh is None:
                continue
            uri = mesh.get('filename')
            base = os.path.basename(uri)
            if 'right_' in base and mirrors(uri, uri[:len(uri) - len(base)] + base.replace('right_', 'left_')):
                uri = uri[:len(uri) - len(base)] + base.replace('right_', 'left_')
                mesh.set('scale', '1 -1 1')
                mirrored += 1
            mesh.set('filename', f'package:///{a.package}/meshes/{collada_for(uri)}')
    for el in robot.findall('mujoco'):
        robot.remove(el)
    out = os.path.join(a.out_dir, a.package, os.path.splitext(os.path.basename(a.urdf))[0] + '_unconventional.urdf')
    tree.write(out)
    print(f'{out}: root {root} turned 180 deg, {sum(not np.allclose(q, np.eye(3)) for q in Q.values())} link frames turned, '
          f'{len(written)} Y_UP millimetre COLLADA meshes, {mirrored} mirrored mesh references, {fingers} finger joints added')


if __name__ == '__main__':
    main()
