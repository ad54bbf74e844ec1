#!/usr/bin/python3
"""Writes pillars.gltf, curved.gltf and terrain.gltf, the small glTF 2.0 scenes of the demo and
tests (one file each, its buffer embedded), and nothing else: their height maps are named by pillars.json,
curved.json and terrain.json, the material tables beside them.

    /usr/bin/python3 data/make_gltf.py [output folder, default: this script's folder]

Standard library only. The scene exercises what a loader must get right:
  - a floor (material "floor") and a back wall ("bricks") at the root;
  - a parent node turned 30 degrees about y holding two boxes ("bricks"), one of them scaled;
  - an elliptic column ("sines"): a cylinder under a non-uniform scale (normals need the inverse
    transpose);
  - a box ("text") under a node with a negative x scale (a mirroring transform: winding flips);
  - a perspective camera node aimed at the scene.
terrain.gltf has no uv at all: a terrain tile of hills cut by a cliff (material "ground") and a
rock of every orientation ("rock"), both triplanar in terrain.json.
curved.gltf is the curved surfaces' test scene: a sphere, a cylinder and a torus standing on
its rim, in bricks at s of 0.06 and 0.1, on a bumpy floor: silhouettes against the background
and against each other. Its meshes are fine enough that no facet departs from the smooth
surface its normals describe by more than 0.2 texel of the relief's depth (half as many segments
put the sphere's at 0.8): the truth displaces the facets, the curved trace follows the smooth
surface, and coarser facets would measure the mesh, not the trace.
uv follow glTF: u to the right, v down an image's rows (so every frame is mirrored, w = -1).
"""
import base64
import json
import math
import os
import struct
import sys


class Builder:
    def __init__(self):
        self.blob = bytearray()
        self.views, self.accessors, self.meshes = [], [], []

    def _view(self, data, target):
        while len(self.blob) % 4:
            self.blob.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data),
                           "target": target})
        self.blob += data
        return len(self.views) - 1

    def _accessor(self, values, kind, width):
        flat = [x for v in values for x in (v if width > 1 else [v])]
        if kind == "index":
            view = self._view(struct.pack("<%dH" % len(flat), *flat), 34963)
            acc = {"bufferView": view, "componentType": 5123, "count": len(flat),
                   "type": "SCALAR"}
        else:
            view = self._view(struct.pack("<%df" % len(flat), *flat), 34962)
            acc = {"bufferView": view, "componentType": 5126, "count": len(values),
                   "type": {2: "VEC2", 3: "VEC3"}[width]}
            if width == 3:
                acc["min"] = [min(v[i] for v in values) for i in range(3)]
                acc["max"] = [max(v[i] for v in values) for i in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def mesh(self, name, material, positions, normals, uvs, indices):
        """uvs None: a mesh without TEXCOORD_0 (for a triplanar material)."""
        attrs = {"POSITION": self._accessor(positions, "f", 3),
                 "NORMAL": self._accessor(normals, "f", 3)}
        if uvs is not None:
            attrs["TEXCOORD_0"] = self._accessor(uvs, "f", 2)
        prim = {"attributes": attrs, "indices": self._accessor(indices, "index", 1),
                "material": material, "mode": 4}
        self.meshes.append({"name": name, "primitives": [prim]})
        return len(self.meshes) - 1


def quad(origin, right, down, tiles_u, tiles_v):
    """A parallelogram: u along `right`, v along `down`, facing cross(down, right)."""
    p = [origin, [origin[i] + right[i] for i in range(3)],
         [origin[i] + right[i] + down[i] for i in range(3)], [origin[i] + down[i] for i in range(3)]]
    n = [down[1] * right[2] - down[2] * right[1], down[2] * right[0] - down[0] * right[2],
         down[0] * right[1] - down[1] * right[0]]
    length = math.sqrt(sum(c * c for c in n))
    n = [c / length for c in n]
    uv = [[0, 0], [tiles_u, 0], [tiles_u, tiles_v], [0, tiles_v]]
    return p, [n] * 4, uv, [0, 3, 2, 0, 2, 1]


def merge(parts):
    pos, nrm, uv, idx = [], [], [], []
    for p, n, t, i in parts:
        base = len(pos)
        pos += p
        nrm += n
        uv += t
        idx += [base + k for k in i]
    return pos, nrm, uv, idx


def box(h, tiles):
    """A cube of half side h centred at the origin, each face upright (v down), one uv square."""
    faces = []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            up = [0, 1, 0] if axis != 1 else [0, 0, -sign]
            right = [up[1] * n[2] - up[2] * n[1], up[2] * n[0] - up[0] * n[2],
                     up[0] * n[1] - up[1] * n[0]]
            origin = [h * (n[i] - right[i] + up[i]) for i in range(3)]
            faces.append(quad(origin, [2 * h * c for c in right], [-2 * h * c for c in up],
                              tiles, tiles))
    return merge(faces)


def column(radius, height, segments, tiles_u, tiles_v):
    """An open upright cylinder on the origin: u around (a seam at angle 0), v from top to bottom."""
    pos, nrm, uv, idx = [], [], [], []
    for s in range(segments + 1):
        a = 2 * math.pi * s / segments
        c, d = math.cos(a), -math.sin(a)
        for top in (1, 0):
            pos.append([radius * c, height * top, radius * d])
            nrm.append([c, 0, d])
            uv.append([tiles_u * s / segments, tiles_v * (1 - top)])
    for s in range(segments):
        t0, b0, t1, b1 = 2 * s, 2 * s + 1, 2 * s + 2, 2 * s + 3
        idx += [t0, b0, b1, t0, b1, t1]
    return pos, nrm, uv, idx


def revolution(rings, segments, tiles_u, tiles_v, place):
    """A surface of revolution about y: ring j of segments + 1 vertices (a seam at angle 0), u
    around, v = tiles_v j / rings; place(j, a) gives ring j's point and normal at angle a."""
    pos, nrm, uv, idx = [], [], [], []
    for j in range(rings + 1):
        for s in range(segments + 1):
            p, n = place(j, 2 * math.pi * s / segments)
            pos.append(p)
            nrm.append(n)
            uv.append([tiles_u * s / segments, tiles_v * j / rings])
    row = segments + 1
    for j in range(rings):
        for s in range(segments):
            k = j * row + s
            idx += [k, k + row, k + row + 1, k, k + row + 1, k + 1]
    return pos, nrm, uv, idx


def sphere(radius, segments, rings, tiles_u, tiles_v):
    """v from the north pole down."""
    def place(j, a):
        theta = math.pi * j / rings
        n = [math.sin(theta) * math.cos(a), math.cos(theta), -math.sin(theta) * math.sin(a)]
        return [radius * c for c in n], n
    return revolution(rings, segments, tiles_u, tiles_v, place)


def torus(radius, tube, segments, rings, tiles_u, tiles_v):
    """About y through the origin; v around the tube from its top, outward first."""
    def place(j, a):
        phi = 2 * math.pi * j / rings
        out = [math.cos(a), 0.0, -math.sin(a)]
        n = [math.sin(phi) * out[0], math.cos(phi), math.sin(phi) * out[2]]
        return [radius * out[i] + tube * n[i] for i in range(3)], n
    return revolution(rings, segments, tiles_u, tiles_v, place)


def gltf(b, name, nodes, roots, materials, eye_target):
    eye, target = eye_target
    nodes = nodes + [{"name": "camera", "camera": 0, "translation": eye,
                      "rotation": look_rotation(eye, target)}]
    return {
        "asset": {"version": "2.0", "generator": "offsetmap data/make_gltf.py"},
        "scene": 0,
        "scenes": [{"name": name, "nodes": roots + [len(nodes) - 1]}],
        "nodes": nodes,
        "meshes": b.meshes,
        "materials": [{"name": m} for m in materials],
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": math.radians(55), "znear": 0.05, "zfar": 40, "aspectRatio": 16 / 9}}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(bytes(b.blob)).decode()}],
    }


def curved(out):
    b = Builder()
    materials = ["floor", "bricks", "bricks deep", "bricks open"]
    floor = b.mesh("floor", 0, *quad([-4, 0, -4], [8, 0, 0], [0, 0, 8], 8 / 1.5, 8 / 1.5))
    ball = b.mesh("sphere", 1, *sphere(0.6, 128, 64, 4, 2))
    # The open cylinder has its own material: its rims are edges the table's tile bounds mark.
    can = b.mesh("cylinder", 3, *column(0.4, 1.4, 128, 3, 2))
    ring = b.mesh("torus", 2, *torus(0.55, 0.22, 192, 96, 6, 2))
    quarter = math.sin(math.radians(45)), math.cos(math.radians(45))
    nodes = [
        {"name": "floor", "mesh": floor},
        {"name": "sphere", "mesh": ball, "translation": [-1.3, 0.6, -1.2]},
        {"name": "cylinder", "mesh": can, "translation": [1.4, 0, -1.8]},
        {"name": "torus", "mesh": ring, "translation": [0.1, 0.77, -0.2],
         "rotation": [quarter[0], 0, 0, quarter[1]]},
    ]
    doc = gltf(b, "curved", nodes, [0, 1, 2, 3], materials, ([0.1, 1.35, 2.3], [-0.05, 0.6, -1.0]))
    with open(os.path.join(out, "curved.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def smooth_normals(pos, idx):
    """Area-weighted vertex normals of counter-clockwise triangles."""
    acc = [[0.0, 0.0, 0.0] for _ in pos]
    for t in range(0, len(idx), 3):
        a, b, c = (pos[idx[t + k]] for k in range(3))
        e1 = [b[i] - a[i] for i in range(3)]
        e2 = [c[i] - a[i] for i in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
             e1[0] * e2[1] - e1[1] * e2[0]]
        for k in range(3):
            for i in range(3):
                acc[idx[t + k]][i] += n[i]
    out = []
    for n in acc:
        length = math.sqrt(sum(x * x for x in n))
        out.append([x / length for x in n])
    return out


def terrain_tile(size, cells):
    """A height field over [-size/2, size/2]^2 (y up): rolling hills and a cliff across it."""
    def height(x, z):
        hills = 0.35 * math.sin(0.9 * x + 0.4) * math.cos(0.7 * z) + 0.12 * math.sin(2.3 * x + 1.7 * z)
        cliff = 1.1 / (1 + math.exp(-(0.8 * x - 0.6 * z + 0.9) / 0.09))
        return hills + cliff
    pos, idx = [], []
    for j in range(cells + 1):
        for i in range(cells + 1):
            x = -size / 2 + size * i / cells
            z = -size / 2 + size * j / cells
            pos.append([x, height(x, z), z])
    for j in range(cells):
        for i in range(cells):
            a = j * (cells + 1) + i
            idx += [a, a + cells + 1, a + 1, a + 1, a + cells + 1, a + cells + 2]
    return pos, smooth_normals(pos, idx), None, idx


def rock(radius, segments, rings):
    """A lumpy ball: every orientation, overhangs included."""
    def r(theta, a):
        return radius * (1 + 0.18 * math.sin(3 * a + 1) * math.sin(2 * theta)
                         + 0.1 * math.cos(5 * theta + 2 * a))
    pos, idx = [], []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments):
            a = 2 * math.pi * i / segments
            k = r(theta, a)
            pos.append([k * math.sin(theta) * math.cos(a), k * math.cos(theta),
                        -k * math.sin(theta) * math.sin(a)])
    for j in range(rings):
        for i in range(segments):
            a, b = j * segments + i, j * segments + (i + 1) % segments
            c, d = a + segments, b + segments
            idx += [a, c, b, b, c, d]
    # The poles' rings are points: their vertices meet in one place, as one vertex would.
    return pos, smooth_normals(pos, idx), None, idx


def terrain(out):
    b = Builder()
    ground = b.mesh("ground", 0, *terrain_tile(8.0, 64))
    stone = b.mesh("rock", 1, *rock(0.7, 48, 24))
    nodes = [
        {"name": "ground", "mesh": ground},
        {"name": "rock", "mesh": stone, "translation": [-1.2, 0.75, 0.9],
         "rotation": [0.2, 0.3, 0.0, math.sqrt(1 - 0.13)]},
    ]
    doc = gltf(b, "terrain", nodes, [0, 1], ["ground", "rock"],
               ([1.6, 2.4, 4.0], [-0.6, 0.5, -0.4]))
    with open(os.path.join(out, "terrain.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def look_rotation(eye, target):
    """The quaternion (x, y, z, w) turning a glTF camera (looking down -z, up +y) toward target."""
    f = [target[i] - eye[i] for i in range(3)]
    fl = math.sqrt(sum(c * c for c in f))
    z = [-c / fl for c in f]
    x = [z[2], 0.0, -z[0]]  # up x z with up = +y
    xl = math.sqrt(sum(c * c for c in x))
    x = [c / xl for c in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    m00, m11, m22 = x[0], y[1], z[2]
    w = math.sqrt(max(0.0, 1 + m00 + m11 + m22)) / 2
    return [(y[2] - z[1]) / (4 * w), (z[0] - x[2]) / (4 * w), (x[1] - y[0]) / (4 * w), w]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    b = Builder()
    materials = ["floor", "bricks", "sines", "text"]
    floor = b.mesh("floor", 0, *quad([-4, 0, -4], [8, 0, 0], [0, 0, 8], 8 / 1.5, 8 / 1.5))
    wall = b.mesh("wall", 1, *quad([-4, 3, -4], [8, 0, 0], [0, -3, 0], 8, 3))
    block = b.mesh("block", 1, *box(0.5, 1))
    col = b.mesh("column", 2, *column(0.35, 1.0, 48, 2, 1))
    text_box = b.mesh("text box", 3, *box(0.4, 1))
    eye, target = [0.4, 1.9, 4.2], [0.0, 0.6, -1.2]
    nodes = [
        {"name": "floor", "mesh": floor},
        {"name": "wall", "mesh": wall},
        {"name": "blocks", "rotation": [0, math.sin(math.radians(15)), 0,
                                        math.cos(math.radians(15))],
         "translation": [-1.6, 0, -1.5], "children": [3, 4]},
        {"name": "block a", "mesh": block, "translation": [0, 0.5, 0]},
        {"name": "block b", "mesh": block, "translation": [0.4, 1.35, 0.1],
         "scale": [0.7, 0.7, 0.7]},
        {"name": "column", "mesh": col, "translation": [1.5, 0, -2.0], "scale": [1.3, 2.2, 0.8]},
        {"name": "mirrored", "mesh": text_box, "translation": [0.6, 0.4, 0.2],
         "scale": [-1, 1, 1]},
    ]
    doc = gltf(b, "pillars", nodes, [0, 1, 2, 5, 6], materials, (eye, target))
    with open(os.path.join(out, "pillars.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    curved(out)
    terrain(out)


if __name__ == "__main__":
    main()
