#!/usr/bin/env python3
"""Writes the diffbot's meshes (assets/robots/diffbot.urdf): ASCII STL in millimetres, as CAD
exports them (the URDF scales them by 0.001), and a COLLADA file that states its unit.
Run from this folder: python3 make_meshes.py"""
import math


def facet(out, a, b, c):
    n = [(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
         (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
         (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])]
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    out.append("  facet normal %g %g %g\n    outer loop\n" % tuple(x / length for x in n))
    for p in (a, b, c):
        out.append("      vertex %.4f %.4f %.4f\n" % p)
    out.append("    endloop\n  endfacet\n")


def box_triangles(sx, sy, sz):
    h = (sx / 2, sy / 2, sz / 2)
    v = [(x * h[0], y * h[1], z * h[2]) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    # Counter-clockwise seen from outside: corner index bits are x (4), y (2), z (1).
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


def wheel_triangles(radius, width, segments):
    """A cylinder along y (the axle), centred on the origin."""
    tris = []
    for k in range(segments):
        a0, a1 = 2 * math.pi * k / segments, 2 * math.pi * (k + 1) / segments
        p = lambda a, y: (radius * math.cos(a), y, radius * math.sin(a))
        l0, l1, r0, r1 = p(a0, width / 2), p(a1, width / 2), p(a0, -width / 2), p(a1, -width / 2)
        tris += [(r0, l1, l0), (r0, r1, l1)]
        tris += [((0, width / 2, 0), l0, l1), ((0, -width / 2, 0), r1, r0)]
    return tris


def write_stl(path, name, tris):
    out = ["solid %s\n" % name]
    for t in tris:
        facet(out, *t)
    out.append("endsolid %s\n" % name)
    with open(path, "w") as f:
        f.writelines(out)


# Chassis: 300 x 180 x 60 mm. Wheel: 90 mm across, 25 mm wide, 24 segments.
write_stl("chassis.stl", "chassis", box_triangles(300, 180, 60))
write_stl("wheel.stl", "wheel", wheel_triangles(45, 25, 24))

# An infrared ranger's housing, 13 x 40 x 14 mm, in millimetres as the file's <unit> says.
tris = box_triangles(13, 40, 14)
positions = " ".join("%g %g %g" % p for t in tris for p in t)
indices = " ".join(str(i) for i in range(3 * len(tris)))
with open("ranger.dae", "w") as f:
    f.write("""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="ranger" name="ranger"><mesh>
      <source id="ranger-pos"><float_array id="ranger-pos-array" count="%d">%s</float_array>
        <technique_common><accessor source="#ranger-pos-array" count="%d" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="ranger-vtx"><input semantic="POSITION" source="#ranger-pos"/></vertices>
      <triangles count="%d"><input semantic="VERTEX" source="#ranger-vtx" offset="0"/><p>%s</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="ranger-node"><instance_geometry url="#ranger"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
""" % (9 * len(tris), positions, 3 * len(tris), len(tris), indices))
