#!/usr/bin/env python3
"""Writes the hand-made seed corpora tests/fuzz/corpus/<target>/ (deterministic output).

Seeds are small valid files and broken ones of each kind, so that a fuzzer starts from every
branch a parser has (see tests/fuzz/README.md). Run it after editing a seed below; the files
are checked in, and tests/test_fuzz_regressions replays them.
"""
import gzip
import math
import os
import random
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")

TETRA_OBJ = b"""# a tetrahedron
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 2 3 4
f 1 4 3
"""

OBJ = {
    "tetra.obj": TETRA_OBJ,
    "tetra.obj.gz": gzip.compress(TETRA_OBJ, mtime=0),
    # a convex quad and pentagon (fans), vt/vn index forms
    "polygons.obj": b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nvt 0 0\nvn 0 0 1\n"
    b"f 1/1/1 2/1/1 3/1/1 4/1/1\nf 1//1 2//1 3//1 5//1 4//1\n",
    # an L-shaped hexagon: ear clipping
    "concave.obj": b"v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n",
    "negative-indices.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -3 -1\n",
    "groups-crlf.obj": b"mtllib none.mtl\r\no thing\r\ng part\r\nusemtl red\r\ns off\r\n"
    b"v +1e-3 -0 2.5E+1\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n",
    "degenerate.obj": b"v 0 0 0\nv 1 1 1\nv 2 2 2\nv 0 1 0\nf 1 2 3\nf 1 1 1\nf 1 2 4\n",
    "unused-nan-vertex.obj": b"v nan 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\n",
    "empty.obj": b"",
    "index-zero.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
    "index-out-of-range.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
    "index-overflow.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n",
    "bad-float.obj": b"v 0 0 x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "nan-vertex.obj": b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "overflow-float.obj": b"v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "no-faces.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\n",
    "two-corners.obj": b"v 0 0 0\nv 1 0 0\nf 1 2\n",
    "unknown-statement.obj": b"v 0 0 0\nbogus 1 2 3\n",
    "truncated.obj.gz": gzip.compress(TETRA_OBJ, mtime=0)[:30],
}

TETRA_VERTICES = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_FACES = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]


def ply_ascii():
    lines = ["ply", "format ascii 1.0", "comment a tetrahedron", "obj_info made by hand",
             "element vertex 4", "property float x", "property float y", "property float z",
             "property uchar red", "element face 4", "property list uchar int vertex_indices",
             "element edge 1", "property int vertex1", "property int vertex2", "end_header"]
    lines += ["%g %g %g 255" % v for v in TETRA_VERTICES]
    lines += ["3 %d %d %d" % f for f in TETRA_FACES]
    lines += ["0 1"]
    return ("\n".join(lines) + "\n").encode()


def ply_binary(endian, xyz_type="float", count_type="uchar", index_type="int", quad=False):
    """A tetrahedron (or a square as one quad) in binary PLY; endian is '<' or '>'."""
    codes = {"float": "f", "double": "d", "uchar": "B", "ushort": "H", "int": "i",
             "uint": "I", "short": "h", "char": "b"}
    name = {"<": "binary_little_endian", ">": "binary_big_endian"}[endian]
    vertices = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)] if quad else TETRA_VERTICES
    faces = [(0, 1, 2, 3)] if quad else TETRA_FACES
    header = ("ply\nformat %s 1.0\nelement vertex %d\nproperty %s x\nproperty %s y\n"
              "property %s z\nproperty short flags\nelement face %d\n"
              "property list %s %s vertex_index\nend_header\n"
              % (name, len(vertices), xyz_type, xyz_type, xyz_type, len(faces), count_type,
                 index_type)).encode()
    body = b""
    for v in vertices:
        body += struct.pack(endian + codes[xyz_type] * 3 + "h", *v, 7)
    for f in faces:
        body += struct.pack(endian + codes[count_type] + codes[index_type] * len(f), len(f), *f)
    return header + body


PLY = {
    "tetra-ascii.ply": ply_ascii(),
    "tetra-little.ply": ply_binary("<"),
    "tetra-big.ply": ply_binary(">"),
    "tetra-big-double-ushort.ply": ply_binary(">", "double", "ushort", "uint"),
    "quad-little-char-short.ply": ply_binary("<", "float", "char", "short", quad=True),
    "tetra-little.ply.gz": gzip.compress(ply_binary("<"), mtime=0),
    "crlf-ascii.ply": ply_ascii().replace(b"\n", b"\r\n"),
    "empty.ply": b"",
    "not-ply.ply": b"plx\nformat ascii 1.0\nend_header\n",
    "no-end-header.ply": b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
    "bad-version.ply": b"ply\nformat ascii 2.0\nend_header\n",
    "forged-count.ply": ply_binary("<").replace(b"element vertex 4", b"element vertex 4000000000"),
    "truncated-little.ply": ply_binary("<")[:-5],
    "index-out-of-range.ply": ply_ascii().replace(b"3 0 2 1", b"3 0 2 9"),
    "nan-vertex.ply": ply_ascii().replace(b"\n0 0 0 255", b"\nnan 0 0 255"),
    "ascii-bad-value.ply": ply_ascii().replace(b"1 0 0 255", b"1 0 zero 255"),
    "uchar-out-of-range.ply": ply_ascii().replace(b"0 0 1 255", b"0 0 1 256"),
    "two-corner-face.ply": ply_ascii().replace(b"3 0 2 1", b"2 0 2"),
    "list-count-float.ply": ply_ascii().replace(b"list uchar int", b"list float int"),
    "truncated.ply.gz": gzip.compress(ply_binary(">"), mtime=0)[:40],
}


def rays(records):
    return b"".join(struct.pack("<8f", *r) for r in records)


INF = math.inf
NAN = math.nan


def camera_rays():
    eye = (2.0, 1.5, -1.0)
    out = []
    for j in range(4):
        for i in range(4):
            target = ((i + 0.5) / 4, (j + 0.5) / 4, 0.5)
            out.append(eye + (0.0,) + tuple(t - e for t, e in zip(target, eye)) + (INF,))
    return out


NASTY_RAYS = [
    (0.5, 0.25, 0.25, 0, 1, 0, 0, INF),         # starts on the mid-plane wall x = 1/2
    (-1, 0.5, 0.5, 0, 1, 0, 0, INF),            # along the axis through a shared edge
    (-1, 0.5, 0.5, 0, 1, -0.0, 0.0, INF),       # -0 component
    (-1, 0.25, 0.25, 0, 1, 1e-30, -1e-30, INF),  # tiny components
    (-1, 0.25, 0.25, 0, 1, 1e-45, 0, INF),      # a denormal component
    (0, 0, 0, 0, 1, 1, 1, INF),                 # from a corner shared by many triangles
    (-1, -1, -1, 0, 1, 1, 1, INF),              # through that corner
    (0.5, 0.5, 2, 0, 0, 0, -1, INF),            # down the line where the mid-planes meet
    (2, 0.5, 0.5, 0.5, -1, 0, 0, 1.0),          # tmax ends exactly on a wall (t = 1.5: past)
    (2, 0.5, 0.5, 0, -1, 0, 0, 1.5),            # tmax exactly at the mid-plane
    (0.25, 0.25, -1, 2, 0, 0, 1, 1),            # tmin > tmax: a miss
    (0.25, 0.25, -1, 0, 0, 0, 0, INF),          # zero direction: a miss
    (NAN, 0, 0, 0, 1, 0, 0, INF),               # NaN origin: a miss
    (0, 0, -1, 0, INF, 0, 1, INF),              # infinite direction: a miss
    (0.25, 0.25, -1, NAN, 0, 0, 1, INF),        # NaN tmin: a miss
    (0.25, 0.25, 0.5, -INF, 0, 0, 1, INF),      # inside, tmin = -inf
]

HITS = [(0, 0.5, 0.25, 0.25), (-1, INF, 0, 0), (17, 1e-30, 0, 1), (2**31 - 1, NAN, -0.0, 2)]

RAYS = {
    "camera.rays": rays(camera_rays()),
    "nasty.rays": rays(NASTY_RAYS),
    "empty.rays": b"",
    "odd-size.rays": rays(NASTY_RAYS[:1]) + b"\0",
}

HIT_FILES = {
    "hits.hits": b"".join(struct.pack("<i3f", *h) for h in HITS),
    "empty.hits": b"",
    "odd-size.hits": b"\0" * 17,
}

CAMERA = "eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40"
STRUCTURE = ["--intcost", "1.5", "--repcost=0.2", "--travcost", "1", "--vertcost", "6",
             "--subcost", "0", "--max-granularity", "8", "--axis", "cost", "--max-depth", "5",
             "--leaf-size", "2", "--density", "0.5", "--sample-every", "3",
             "--memory-budget", "64M", "--build-threads", "1"]
CLI = {
    "trace": ["trace", "builtin:pyramid", "--rays", "a.rays", "--out", "a.hits", "--accel",
              "grid1d", "--threads", "2", "--stats", "s.json", "--eager", "--occluded",
              "--repeat", "3"] + STRUCTURE,
    "trace-walk": ["trace", "scene.obj.gz", "--rays=a.rays", "--out=a.hits", "--walk", "3",
                   "--walk-out", "w.json", "--sample-image", "64x48"],
    "trace-zero": ["trace", "x.ply", "--rays", "a.rays", "--out", "b.hits", "--accel", "zero",
                   "--oracle", "a.hits"],
    "render": ["render", "builtin:lumpy", "--out", "x.png", "--size", "64x48", "--camera",
               CAMERA, "--spp", "4", "--accel", "bvh", "--threads", "1", "--stats", "s.json"],
    "shot": ["shot", "builtin:pyramid", "--out", "x.png", "--overlay",
             "cells,states,walk,heat:steps", "--pixel", "3,4", "--ui", "--accel", "grid1d"],
    "view": ["view", "--frames", "3", "--click", "0.5,0.5", "--screenshot", "s.png",
             "--walk-out", "w.json", "--size", "800x600", "--overlay", "heat:tests"],
    "view-scene": ["view", "builtin:sphereflake", "--camera", CAMERA, "--accel", "brute"],
    "export": ["export", "builtin:lumpy", "--out", "x.obj"],
    "rays": ["rays", "builtin:sphereflake", "--out", "v.rays", "--size", "8x8", "--camera",
             CAMERA],
    "help": ["help"],
    "trace-help": ["trace", "--help"],
    "bench": ["bench", "--scenes", "builtin:pyramid", "--accels", "grid1d,bvh", "--out", "d",
              "--quick", "--seed", "3"],
    "calibrate": ["calibrate", "--out", "c.json"],
    "no-command": [],
    "unknown-command": ["frobnicate"],
    "trace-no-rays": ["trace", "builtin:pyramid", "--out", "a.hits"],
    "bad-size": ["render", "builtin:pyramid", "--out", "x.png", "--size", "0x5"],
    "bad-threads": ["trace", "s.obj", "--rays", "r", "--out", "h", "--threads", "0"],
    "bad-camera": ["render", "s.obj", "--out", "x.png", "--camera", "eye=0,0,0;target=0,0,0"],
    "bad-budget": ["trace", "s.obj", "--rays", "r", "--out", "h", "--memory-budget", "9e99G"],
    "bad-depth": ["render", "s.obj", "--out", "x.png", "--max-depth", "65"],
    "missing-value": ["view", "--frames"],
    "bad-click": ["view", "--click", "2,2"],
    "switch-with-value": ["shot", "s.obj", "--out", "x.png", "--ui=1"],
}


def differential_seeds():
    """Byte strings the differential entry reads as choices (any bytes are a valid case)."""
    seeds = {"empty": b"", "ones": b"\x01" * 512, "ascending": bytes(range(256)) * 2}
    rng = random.Random(1990)
    for n in (64, 256, 1024, 2048):
        seeds["random-%d" % n] = bytes(rng.randrange(256) for _ in range(n))
    return seeds


def write(target, files):
    folder = os.path.join(CORPUS, target)
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    for name, data in files.items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)


def main():
    write("obj", OBJ)
    write("ply", PLY)
    write("rays", RAYS)
    write("hits", HIT_FILES)
    write("cli", {name: b"".join(w.encode() + b"\0" for w in words)
                  for name, words in CLI.items()})
    write("differential", differential_seeds())


if __name__ == "__main__":
    main()
