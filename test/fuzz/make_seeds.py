#!/usr/bin/python3
"""Writes the fuzz targets' seed corpora, test/fuzz/corpus/<name>/ (small valid inputs each).

The targets read their bytes with libFuzzer's FuzzedDataProvider (test/fuzz/<name>.cpp), which
takes whole numbers and floating-point values from the end of the input and strings and the
remaining bytes from the front; `Seed` writes what the provider reads back, in the order a
target consumes it. The file-based targets (mesh, config) get their files with a leading selector
byte. Run from anywhere: /usr/bin/python3 test/fuzz/make_seeds.py (python3-opencv for the
compressed images). Rewrites the corpus directories.
"""

import math
import shutil
import struct
from pathlib import Path

import cv2
import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CORPUS = HERE / "corpus"
U64 = 2**64 - 1
U32 = 2**32 - 1


class Seed:
    """The bytes FuzzedDataProvider turns back into the values given, in consumption order."""

    def __init__(self):
        self.front = bytearray()  # strings, remaining bytes: read from the front
        self.tail = bytearray()  # numbers: read from the end, in this order

    def int(self, value, lo, hi):
        span = hi - lo
        assert lo <= value <= hi, (value, lo, hi)
        nbytes = 0
        while nbytes < 8 and (span >> (8 * nbytes)) > 0:
            nbytes += 1
        r = value - lo
        # The first byte read (the input's last) is the most significant.
        self.tail += bytes((r >> (8 * (nbytes - 1 - k))) & 0xFF for k in range(nbytes))
        return self

    def bool(self, value):
        return self.int(1 if value else 0, 0, 255)

    def u32(self, value):
        return self.int(value, 0, U32)

    def u8(self, value):
        return self.int(value, 0, 255)

    def f64(self, value, lo, hi):  # ConsumeFloatingPointInRange<double>(lo, hi), no split range
        self.int(min(U64, max(0, round((value - lo) / (hi - lo) * U64))), 0, U64)
        return self

    def f32(self, value, lo, hi):  # ConsumeFloatingPointInRange<float>(lo, hi)
        self.int(min(U32, max(0, round((value - lo) / (hi - lo) * U32))), 0, U32)
        return self

    def string(self, s):  # ConsumeRandomLengthString: '\' + another byte ends it
        self.front += s.replace(b"\\", b"\\\\") + b"\\x"
        return self

    def rest(self, data):  # ConsumeRemainingBytes
        self.front += data
        return self

    def bytes(self):
        return bytes(self.front) + bytes(reversed(self.tail))


# The targets' helpers (fuzz_common.hpp).
def count_usual(s, value, usual):  # count<T>(p, usual) within usual
    s.int(1, 0, 7)
    return s.int(value, 0, usual)


def name(s, names, value):  # name(p, names): one of them
    s.int(1, 0, 7)
    return s.int(names.index(value), 0, len(names) - 1)


def number(s, value, rng):  # number(p, range): a plain value in [-range, range]
    s.int(6, 0, 15)
    return s.f64(value, -rng, rng)


def number_special(s, which, positive=True):
    """number(p, range) as NaN, inf, 1e300, denorm or zero."""
    case = {"nan": 0, "inf": 1, "huge": 2, "denorm": 3, "zero": 4}[which]
    s.int(case, 0, 15)
    if case in (1, 2, 3):
        s.bool(positive)
    return s


def write(target, name_, data):
    d = CORPUS / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name_).write_bytes(data)


# ----------------------------------------------------------------------------------- cloud
def floats(values, big_endian=False):
    return struct.pack((">" if big_endian else "<") + "%df" % len(values), *values)


def cloud_seeds():
    fields = [("x", 0), ("y", 4), ("z", 8), ("intensity", 12)]
    names = ["x", "y", "z", "intensity", "ring"]

    def layout(s, organized, height, width):
        s.int(0 if organized else 1, 0, 3)
        if not organized:
            count_usual(s, height, 4)
            count_usual(s, width, 64)
        s.bool(True).int(4, 3, 8)  # point_step 16
        return s

    def add_fields(s, fields_):  # float32, count 1
        s.int(len(fields_), 0, 6)
        for n, off in fields_:
            name(s, names, n)
            s.bool(True).int(off // 4, 0, 7).bool(True).bool(True)

    # A VLP-16 (the default model) and an unorganized ring of 64 points 3 m around it.
    s = Seed().bool(False)
    layout(s, False, 1, 64)
    s.bool(False).bool(True)  # little-endian, dense
    add_fields(s, fields)
    s.int(1, 0, 3)  # consistent rows
    pts = []
    for k in range(64):
        a = 2 * math.pi * k / 64
        pts += [3 * math.cos(a), 3 * math.sin(a), 0.1 * math.sin(3 * a), 100.0]
    write("cloud", "vlp16_ring", s.rest(floats(pts)).bytes())

    # An 8 x 4 model and an organized big-endian cloud of its size, some points without return.
    s = Seed().bool(True).bool(True).int(8, 1, 8).bool(True).int(4, 1, 4)
    s.f64(-0.2, -1.5708, 1.5708).f64(0.2, -1.5708, 1.5708)
    s.int(0, 0, 3)  # organized
    s.bool(True).int(4, 3, 8)
    s.bool(True).bool(False)  # big-endian, not dense
    add_fields(s, fields)
    s.int(1, 0, 3)
    pts = []
    for k in range(32):
        pts += [2.0, 0.1 * (k % 8) - 0.4, 0.1 * (k // 8) - 0.2, 1.0] if k % 5 else [math.nan] * 4
    write("cloud", "organized_8x4_big_endian", s.rest(floats(pts, big_endian=True)).bytes())

    # z is float64: refused.
    s = Seed().bool(False)
    layout(s, False, 1, 4)
    s.bool(False).bool(True)
    s.int(3, 0, 6)
    for n, off in [("x", 0), ("y", 4)]:
        name(s, names, n)
        s.bool(True).int(off // 4, 0, 7).bool(True).bool(True)
    name(s, names, "z")
    s.bool(True).int(2, 0, 7).bool(False).u8(8).bool(True)
    s.int(1, 0, 3)
    write("cloud", "z_float64", s.rest(floats([1, 2, 3, 4] * 4)).bytes())

    # Rows padded beyond width x point_step (row_step 80 for 4 points of 16 bytes), 2 rows.
    s = Seed().bool(False)
    layout(s, False, 2, 4)
    s.bool(False).bool(True)
    add_fields(s, fields[:3])
    s.int(0, 0, 3)  # row_step and data as given
    count_usual(s, 80, 4096)
    write("cloud", "padded_rows", s.rest(floats([1.0, -1.0, 0.2, 0.0] * 10 * 2)).bytes())


# ----------------------------------------------------------------------------------- images
ENCODINGS = ["32FC1", "16UC1", "mono16", "rgb8", "bgr8", "rgba8", "bgra8", "mono8", "8UC3",
             "16UC3", "32FC3", "bayer_rggb8", "yuv422", "64FC1"]
FORMATS = ["jpeg", "png", "rgb8; jpeg compressed bgr8", "bgr8; png compressed bgr8",
           "mono8; png compressed mono8", "16UC1; png compressed", "mono16; png compressed mono16",
           "16UC1; compressedDepth png", "32FC1; compressedDepth", "32FC1; compressedDepth png",
           "rgba8; jpeg compressed bgr8", "bgr8; compressedDepth", "compressedDepth"]


def camera(s, width, height, f):
    s.int(2, 0, 7).int(width, 0, 64)
    s.int(2, 0, 7).int(height, 0, 48)
    s.int(1, 0, 3).f64(f, 1.0, 200.0).f64(f, 1.0, 200.0)
    return s


def raw_image(encoding, width, height, pixels, f=50.0):
    s = Seed().bool(False)
    camera(s, width, height, f)
    name(s, ENCODINGS, encoding)
    s.int(1, 0, 3)  # the camera's size
    s.int(1, 0, 7)  # little-endian
    s.int(1, 0, 3)  # consistent step and data
    return s.rest(pixels).bytes()


def compressed_image(fmt, data, width, height):
    s = Seed().bool(True)
    camera(s, width, height, 50.0)
    name(s, FORMATS, fmt)
    return s.rest(data).bytes()


def images_seeds():
    write("images", "depth_32fc1_64x48",
          raw_image("32FC1", 64, 48, floats([1.0, 1.5, math.nan, 0.0, 2.25, -1.0, math.inf, 0.8])))
    write("images", "depth_16uc1_32x24",
          raw_image("16UC1", 32, 24, struct.pack("<8H", 0, 800, 1200, 65535, 1000, 1, 5000, 999),
                    f=30.0))
    write("images", "rgb8_64x48", raw_image("rgb8", 64, 48, bytes(range(0, 240, 10))))
    write("images", "bgra8_16x12", raw_image("bgra8", 16, 12, bytes(range(0, 256, 16))))
    write("images", "mono8_8x6", raw_image("mono8", 8, 6, bytes([0, 50, 100, 150, 200, 250])))
    rng = np.random.default_rng(1)
    bgr = rng.integers(0, 255, (12, 16, 3), dtype=np.uint8)
    write("images", "png_bgr8_16x12",
          compressed_image("bgr8; png compressed bgr8", cv2.imencode(".png", bgr)[1].tobytes(), 16, 12))
    write("images", "jpeg_rgb8_16x12",
          compressed_image("rgb8; jpeg compressed bgr8",
                           cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, 50])[1].tobytes(), 16, 12))
    gray = rng.integers(0, 255, (6, 8), dtype=np.uint8)
    write("images", "png_mono8_8x6",
          compressed_image("mono8; png compressed mono8", cv2.imencode(".png", gray)[1].tobytes(), 8, 6))
    depth_mm = rng.integers(0, 3000, (12, 16), dtype=np.uint16)
    depth_mm[0, :4] = 0
    png16 = cv2.imencode(".png", depth_mm)[1].tobytes()
    write("images", "compressed_depth_16uc1_16x12",
          compressed_image("16UC1; compressedDepth png", struct.pack("<iff", 0, 0, 0) + png16, 16, 12))
    # 32FC1: inverse depth, depth = a / (v - b).
    inv = rng.integers(1000, 60000, (12, 16), dtype=np.uint16)
    inv[3, 3] = 0
    write("images", "compressed_depth_32fc1_16x12",
          compressed_image("32FC1; compressedDepth",
                           struct.pack("<iff", 0, 3000.0, -1.0) + cv2.imencode(".png", inv)[1].tobytes(),
                           16, 12))


# ----------------------------------------------------------------------------------- hypotheses
def optical_look_at(eye, target):
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = eye
    return T


def quaternion(R):  # w, x, y, z of a rotation matrix
    w = math.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return w, x, y, z


def hypotheses_seeds():
    frames_ = ["camera", "camera", "detector", "nowhere"]
    classes = ["box", "box", "cylinder", "unknown", ""]
    T_base_camera = optical_look_at(np.array([0.0, 0.0, 1.2]), np.array([1.0, 0.0, 0.7]))
    T_map_box = np.eye(4)
    T_map_box[:3, :3] = [[math.cos(0.3), -math.sin(0.3), 0], [math.sin(0.3), math.cos(0.3), 0], [0, 0, 1]]
    T_map_box[:3, 3] = [1.0, 0.0, 0.75]
    T_camera_box = np.linalg.inv(T_base_camera) @ T_map_box
    q_camera = quaternion(T_camera_box[:3, :3])
    q_base = quaternion(T_map_box[:3, :3])

    def options(s, search=False):
        s.int(1, 1, 3).int(1, 1, 3).bool(search).bool(False).bool(True)

    def frame(s, frame_id, hyps):
        s.int(1, 0, 7)  # stamped with the image
        name(s, frames_, frame_id)
        s.int(len(hyps), 0, 6)
        for cls, offset, q, score in hyps:
            name(s, classes, cls)
            s.int(1, 0, 3)  # near the box
            for o in offset:
                s.f64(o, -0.3, 0.3)
            s.int(1, 0, 3)
            for c in q:
                s.f64(c, -1.0, 1.0)
            s.int(1, 0, 3).f32(score, 0.0, 1.0)

    # The box seen in three frames, detected where it is (a little off in the second).
    s = Seed()
    options(s)
    s.int(3, 1, 3).f64(0.1, 0.02, 1.0)
    frame(s, "camera", [("box", (0, 0, 0), q_camera, 0.9)])
    frame(s, "camera", [("box", (0.02, -0.01, 0.01), q_camera, 0.8)])
    frame(s, "camera", [("box", (0, 0, 0), q_camera, 0.95)])
    write("hypotheses", "box_three_frames", s.bytes())

    # In the base frame: the box, a cylinder beside it, a class the catalog lacks; orientation
    # search on.
    s = Seed()
    options(s, search=True)
    s.int(2, 1, 3).f64(0.2, 0.02, 1.0)
    hyps = [("box", (0, 0, 0), q_base, 0.9), ("cylinder", (0.0, 0.2, 0.05), (1, 0, 0, 0), 0.7),
            ("unknown", (0.1, 0.1, 0), (1, 0, 0, 0), 0.9)]
    frame(s, "detector", hyps)
    frame(s, "detector", hyps[:2])
    write("hypotheses", "detector_frame_three_classes", s.bytes())

    # A NaN position, a zero quaternion and a non-finite score beside a good hypothesis.
    s = Seed()
    options(s)
    s.int(1, 1, 3).f64(0.1, 0.02, 1.0)
    s.int(1, 0, 7)
    name(s, frames_, "camera")
    s.int(4, 0, 6)
    name(s, classes, "box")  # NaN position
    s.int(0, 0, 3)
    number_special(s, "nan")
    number(s, 0.0, 1e3)
    number(s, 1.0, 1e3)
    s.int(1, 0, 3).f64(1, -1, 1).f64(0, -1, 1).f64(0, -1, 1).f64(0, -1, 1)
    s.int(1, 0, 3).f32(0.9, 0, 1)
    name(s, classes, "box")  # zero quaternion
    s.int(1, 0, 3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3)
    s.int(1, 0, 3).f64(0, -1, 1).f64(0, -1, 1).f64(0, -1, 1).f64(0, -1, 1)
    s.int(1, 0, 3).f32(0.9, 0, 1)
    name(s, classes, "box")  # infinite score
    s.int(1, 0, 3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3)
    s.int(1, 0, 3)
    for c in q_camera:
        s.f64(c, -1.0, 1.0)
    s.int(0, 0, 3)
    number_special(s, "inf")
    name(s, classes, "box")  # a good one
    s.int(1, 0, 3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3).f64(0, -0.3, 0.3)
    s.int(1, 0, 3)
    for c in q_camera:
        s.f64(c, -1.0, 1.0)
    s.int(1, 0, 3).f32(0.9, 0, 1)
    write("hypotheses", "non_finite_beside_good", s.bytes())


# ----------------------------------------------------------------------------------- yolo_pose
def yolo_pose_seeds():
    def seed(input_wh, classes, keypoints, image_wh, anchors, values, thresholds=None,
             channels=None):
        s = Seed().int(input_wh[0], 1, 640).int(input_wh[1], 1, 640)
        s.int(classes, 1, 8).int(keypoints, 0, 12)
        s.bool(thresholds is not None)
        if thresholds is not None:
            for t in thresholds:
                s.bool(t is not None)
                if t is not None:
                    number(s, t, 1.0)
        s.bool(True)  # default decode options
        s.int(image_wh[0], -1, 2000).int(image_wh[1], -1, 2000)
        s.int(1, 0, 15).int(1, 0, 15)  # 1 x C x N float
        if channels is None:
            s.int(1, 0, 7)
        else:
            s.int(0, 0, 7).int(channels, 1, 64)
        s.int(anchors, 1, 64)
        s.int(1, 0, 15)
        for v in values:
            if 0.0 <= v <= 1.0:
                s.bool(True).f32(v, 0.0, 1.0)
            else:
                s.bool(False)
                number(s, v, 400.0)
        return s.bytes()

    # 2 classes, 9 keypoints (33 channels), 3 anchors, a 640 x 480 image in a 320 x 320 input.
    C, N = 4 + 2 + 27, 3
    out = np.zeros((C, N))
    out[0:4, 0] = [160, 160, 80, 60]
    out[4:6, 0] = [0.9, 0.1]
    out[0:4, 1] = [165, 158, 78, 62]  # overlaps anchor 0: suppressed
    out[4:6, 1] = [0.8, 0.05]
    out[0:4, 2] = [60, 200, 30, 30]
    out[4:6, 2] = [0.2, 0.7]
    for k in range(9):
        out[6 + 3 * k:9 + 3 * k, 0] = [130 + 7 * k, 140 + 5 * k, 0.9]
        out[6 + 3 * k:9 + 3 * k, 2] = [50 + k, 190 + k, 0.5]
    write("yolo_pose", "two_classes_nine_keypoints",
          seed((320, 320), 2, 9, (640, 480), N, out.flatten().tolist()))
    # 5 classes, no keypoints, per-class thresholds, 2 anchors.
    C, N = 9, 2
    out = np.zeros((C, N))
    out[:, 0] = [100, 100, 20, 20, 0.4, 0.6, 0.1, 0.0, 0.3]
    out[:, 1] = [50, 60, 10, 12, 0.0, 0.0, 0.0, 0.95, 0.2]
    write("yolo_pose", "per_class_thresholds",
          seed((256, 192), 5, 0, (64, 48), N, out.flatten().tolist(),
               thresholds=[0.5, 0.7, None, 0.9, None]))
    # A blob with more channels than the metadata says: refused.
    write("yolo_pose", "channel_mismatch",
          seed((320, 320), 1, 9, (320, 320), 2, [0.5] * 64, channels=32))


# ----------------------------------------------------------------------------------- semap
def semap_seeds():
    ids = ["a", "b", "c", "klt_1", "box_1", "map", ""]
    classes = ["klt", "box", "unknown", ""]

    def pose(s, t, q):
        s.int(1, 0, 3)
        for v in t:
            s.f64(v, -5.0, 5.0)
        for v in q:
            s.f64(v, -1.0, 1.0)

    def graph(nodes, edges=()):
        s = Seed().bool(True).f64(1700000000.5, 0.0, 2e9).bool(True)
        s.int(1, 0, 63).int(len(nodes), 0, 12)
        for id_, cls, parent, t, q in nodes:
            name(s, ids, id_)
            name(s, classes, cls)
            name(s, ids, parent)
            pose(s, t, q)
        s.int(len(edges), 0, 3)
        for sub, rel, obj in edges:
            name(s, ids, sub)
            name(s, ids, obj)
            name(s, ["on", "in", "left_of", "above"], rel)
        return s.bytes()

    c, sn = math.cos(0.2), math.sin(0.2)
    write("semap_bridge", "graph_klt_with_box_inside",
          graph([("klt_1", "klt", "map", (1.0, 0.5, 0.8), (c, 0, 0, sn)),
                 ("box_1", "box", "klt_1", (0.0, 0.0, 0.05), (1, 0, 0, 0)),
                 ("a", "unknown", "map", (2.0, 0.0, 0.0), (1, 0, 0, 0))],
                [("box_1", "in", "klt_1")]))
    write("semap_bridge", "graph_cycle",
          graph([("a", "klt", "b", (0.1, 0, 0), (1, 0, 0, 0)),
                 ("b", "box", "a", (0.1, 0, 0), (1, 0, 0, 0))]))
    write("semap_bridge", "graph_duplicate_id",
          graph([("a", "klt", "map", (0.1, 0, 0), (1, 0, 0, 0)),
                 ("a", "box", "map", (0.2, 0, 0), (1, 0, 0, 0))]))

    s = Seed().bool(True).f64(1700000001.0, 0.0, 2e9).bool(False)
    s.int(1, 0, 63).int(2, 0, 12)
    for id_, cls, parent, t in [("klt_1", "klt", "map", (1.0, 0.5, 0.8)),
                                ("b", "unknown", "klt_1", (1.0, 0.5, 0.9))]:
        name(s, ids, id_)
        name(s, classes, cls)
        name(s, ids, parent)
        s.u8(1)
        number(s, 0.8, 1.0)
        pose(s, t, (1, 0, 0, 0))
    write("semap_bridge", "tracked_objects", s.bytes())


# ----------------------------------------------------------------------------------- mesh
TETRA_PLY = b"""ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 0
0.1 0 0
0 0.1 0
0 0 0.1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
"""

CUBE_OBJ = b"""# unit cube in decimetres
v -0.05 -0.05 -0.05
v 0.05 -0.05 -0.05
v 0.05 0.05 -0.05
v -0.05 0.05 -0.05
v -0.05 -0.05 0.05
v 0.05 -0.05 0.05
v 0.05 0.05 0.05
v -0.05 0.05 0.05
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
"""

TETRA_OFF = b"""OFF
4 4 6
0 0 0
0.1 0 0
0 0.1 0
0 0 0.1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
"""

TRIANGLE_STL = b"""solid t
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 0.1 0 0
  vertex 0 0.1 0
 endloop
endfacet
endsolid t
"""


def binary_ply(vertices, faces):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar uint vertex_indices\nend_header\n" % (len(vertices), len(faces)))
    body = b"".join(struct.pack("<3f", *v) for v in vertices)
    body += b"".join(struct.pack("<B3I", 3, *f) for f in faces)
    return head.encode() + body


def mesh_seeds():
    ext = {".ply": 0, ".obj": 1, ".stl": 2, ".off": 3}
    write("mesh", "tetra_ascii.ply", bytes([ext[".ply"], 0]) + TETRA_PLY)
    write("mesh", "tetra_binary.ply", bytes([ext[".ply"], 0]) + binary_ply(
        [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1)], [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]))
    write("mesh", "cube_quads.obj", bytes([ext[".obj"], 16]) + CUBE_OBJ)
    write("mesh", "tetra.off", bytes([ext[".off"], 0]) + TETRA_OFF)
    write("mesh", "triangle_ascii.stl", bytes([ext[".stl"], 1]) + TRIANGLE_STL)  # scale 0.001
    # A small binary STL of the package (relay.stl, 11 kB), with the 5 m extent limit.
    write("mesh", "relay_binary.stl", bytes([ext[".stl"], 16]) + (ROOT / "meshes/relay.stl").read_bytes())
    # A degenerate triangle beside a good one, not dropped: refused.
    write("mesh", "degenerate_kept.off", bytes([ext[".off"], 8]) +
          b"OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n")


# ----------------------------------------------------------------------------------- config
SCENARIO = b"""# A scenario on the fuzz target's fixtures (catalog.yaml, floor.ply beside it).
duration: 1.0
seed: 3
world: {mesh: floor.ply, workbench: [1.0, 0.0, 0.01]}
catalog: catalog.yaml
objects:
  - {id: box_1, class: box, frame: workbench, keyframes: [{t: 0, xyz: [0, 0, 0.05], rpy_deg: [0, 0, 30]}]}
  - id: cylinder_1
    class: cylinder
    inside: {container: box_1, from: 0.5}
    keyframes: [{t: 0, xyz: [1.3, 0, 0.1]}, {t: 0.5, xyz: [1.0, 0, 0.1], rpy: [0, 0, 1]}]
distractors:
  - {id: person, shape: cylinder, radius: 0.2, height: 1.7, keyframes: [{t: 0, xyz: [0, 1, 0.85]}]}
  - {id: crate, shape: box, size: [0.3, 0.2, 0.2], frame: workbench, keyframes: [{t: 0, xyz: [0.3, 0, 0.1]}]}
relations:
  - {subject: box_1, relation: left_of, object: crate, from: 0.0, to: 0.8}
robot:
  keyframes: [{t: 0, xy: [0, 0], yaw_deg: 0}, {t: 1, xy: [0.2, 0], yaw: 0.1}]
camera:
  width: 64
  height: 48
  fx: 50
  fy: 50
  rate: 10
  mount: {xyz: [0.1, 0, 1.2], look_at: [0, 0, 0], look_at_frame: workbench}
lidar: {rate: 5, range_max: 30, mount: {xyz: [0, 0, 0.9], rpy_deg: [0, 0, 0]}}
noise: {depth_sigma_at_1m: 0.001, odometry: {translation_sigma: 0.01, initial_error: [0.01, 0, 0]}}
detections: {min_visible_pixels: 20, miss_probability: 0.1}
"""

SCENARIO_URDF = b"""duration: 2
world: {urdf: map.urdf}
catalog: catalog.yaml
objects:
  - {id: b, class: box, keyframes: [{t: 0, xyz: [1, 0, 0.05]}]}
robot: {keyframes: [{t: 0, xy: [0, 0]}]}
"""

SCENARIO_BUILDING = b"""duration: 0.5
world:
  building: {length_x: 6, length_y: 5, rooms_x: 1, rooms_y: 1, tile_size: 2, target_triangles: 0, furniture: false}
catalog: catalog.yaml
robot: {frame: workbench, keyframes: [{t: 0, xy: [0, 1.0], yaw_deg: -90}]}
"""

CATALOG = b"""mesh_dir: .
objects:
  box:
    mesh: box.stl
    symmetries_discrete: [[-1, 0, 0, 0,  0, -1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1]]
  cylinder:
    mesh: file://cylinder.stl
    scale: 0.5
    symmetries_continuous: [{axis: [0, 0, 1], offset: [0, 0, 0]}]
  floor: {mesh: floor.ply}
"""

URDF = b"""<?xml version="1.0"?>
<robot name="bench">
  <link name="floor">
    <visual><geometry><box size="4 4 0.02"/></geometry></visual>
  </link>
  <link name="table">
    <visual><origin xyz="0 0 0.35"/><geometry><box size="0.8 0.6 0.7"/></geometry></visual>
    <visual><origin xyz="0.3 0 0.75" rpy="0 0 0.5"/><geometry><mesh filename="box.stl" scale="1 1 2"/></geometry></visual>
  </link>
  <link name="post">
    <visual><geometry><cylinder radius="0.05" length="1.0"/></geometry></visual>
  </link>
  <link name="ball">
    <visual><origin xyz="0 0 0.6"/><geometry><sphere radius="0.1"/></geometry></visual>
  </link>
  <joint name="floor_table" type="fixed"><parent link="floor"/><child link="table"/><origin xyz="1 0 0"/></joint>
  <joint name="floor_post" type="fixed"><parent link="floor"/><child link="post"/><origin xyz="-1 0 0.5" rpy="0 0.1 0"/></joint>
  <joint name="post_ball" type="revolute"><parent link="post"/><child link="ball"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def config_seeds():
    write("config", "catalog_package_objects.yaml", b"\x00" + (ROOT / "config/objects.yaml").read_bytes())
    write("config", "catalog_fixtures.yaml", b"\x00" + CATALOG)
    write("config", "catalog_override.yaml", b"\x03objects:\n  box: {mesh: elsewhere/box.stl}\n")
    write("config", "scenario_mesh_world.yaml", b"\x01" + SCENARIO)
    write("config", "scenario_urdf_world.yaml", b"\x01" + SCENARIO_URDF)
    write("config", "scenario_small_building.yaml", b"\x01" + SCENARIO_BUILDING)
    write("config", "map.urdf", b"\x02" + URDF)


def main():
    for target, make in [("cloud", cloud_seeds), ("images", images_seeds),
                         ("hypotheses", hypotheses_seeds), ("yolo_pose", yolo_pose_seeds),
                         ("semap_bridge", semap_seeds), ("mesh", mesh_seeds),
                         ("config", config_seeds)]:
        shutil.rmtree(CORPUS / target, ignore_errors=True)
        make()
        files = sorted((CORPUS / target).iterdir())
        print("%-13s %2d seeds, %6d bytes" % (target, len(files), sum(f.stat().st_size for f in files)))


if __name__ == "__main__":
    main()
