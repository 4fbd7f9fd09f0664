#!/usr/bin/env python3
"""Writes the binary seeds of the message fuzz targets: ROS-serialized messages, valid and
invalid, as a subscriber receives them (genpy serializes as roscpp does).

    /usr/bin/python3 src/aar_testing/fuzz/make_seeds.py src/aar_testing/fuzz/corpus

point_cloud/: one sensor_msgs/PointCloud2 per file. stereo_input/: left and right
sensor_msgs/CameraInfo, then left and right sensor_msgs/Image, back to back. The text seeds
(flight paths, meshes, URDFs, YAML) are copies or cut-downs of the shipped files (README.md).
"""
import io
import math
import os
import random
import struct
import sys

from sensor_msgs.msg import CameraInfo, Image, PointCloud2, PointField

F32 = PointField.FLOAT32
U8 = PointField.UINT8


def serialize(*msgs):
    buf = io.BytesIO()
    for m in msgs:
        m.serialize(buf)
    return buf.getvalue()


def cloud(fields, points, width=None, height=1, row_pad=0, frame="stereo_left_optical"):
    """fields: [(name, datatype)] packed in order; points: tuples of values."""
    fmt_of = {F32: "f", U8: "B", PointField.FLOAT64: "d", PointField.INT32: "i",
              PointField.UINT16: "H"}
    msg = PointCloud2()
    msg.header.frame_id = frame
    msg.header.seq = 7
    offset = 0
    fmt = "<"
    for name, datatype in fields:
        msg.fields.append(PointField(name=name, offset=offset, datatype=datatype, count=1))
        offset += struct.calcsize("<" + fmt_of[datatype])
        fmt += fmt_of[datatype]
    msg.point_step = offset
    msg.width = len(points) // height if width is None else width
    msg.height = height
    msg.row_step = msg.width * msg.point_step + row_pad
    data = b""
    for r in range(height):
        for c in range(msg.width):
            data += struct.pack(fmt, *points[r * msg.width + c])
        data += b"\0" * row_pad
    msg.data = data
    msg.is_dense = all(all(math.isfinite(v) for v in p) for p in points)
    return msg


def point_cloud_seeds():
    xyz = [("x", F32), ("y", F32), ("z", F32)]
    nan = float("nan")
    seeds = {}
    seeds["xyz_one_nan"] = cloud(xyz, [(1, 2, 40), (nan, 0, 0), (-1, 0.5, 41), (0, 0, 39)])
    seeds["organized_padded_rows"] = cloud(
        xyz, [(i, -i, 30 + i) for i in range(6)], height=2, row_pad=4)
    # The occlusion stage's reference cloud: normals, visibility class, packed colour.
    reference = xyz + [("normal_x", F32), ("normal_y", F32), ("normal_z", F32),
                       ("visibility", U8), ("rgb", F32)]
    seeds["reference_with_classes"] = cloud(
        reference, [(1, 0, 0, 1, 0, 0, 0, 0.0), (0, 1, 0, 0, 1, 0, 3, 0.0),
                    (0, 0, 1, 0, 0, 1, 1, 0.0)], frame="receiver")
    seeds["stereo_with_intensity"] = cloud(
        xyz + [("intensity", F32)], [(0.1, 0.2, 50, 17), (0.3, 0.1, 51, 200)])
    seeds["other_types"] = cloud(
        xyz + [("ring", PointField.UINT16), ("t", PointField.FLOAT64), ("id", PointField.INT32)],
        [(1, 1, 1, 3, 0.25, -7), (2, 2, 2, 4, 0.5, 9)])
    seeds["empty"] = cloud(xyz, [])
    seeds["all_nan"] = cloud(xyz, [(nan, nan, nan)] * 3)
    seeds["huge_coordinates"] = cloud(xyz, [(0, 0, 1e20), (0, 0, 3e38), (1, 1, 40)])
    missing_z = cloud([("x", F32), ("y", F32)], [(1, 2), (3, 4)])
    seeds["no_z"] = missing_z
    short = cloud(xyz, [(1, 2, 3), (4, 5, 6)])
    short.data = short.data[:-3]
    seeds["data_too_short"] = short
    beyond = cloud(xyz, [(1, 2, 3)])
    beyond.fields[2].offset = 10
    seeds["field_beyond_point_step"] = beyond
    big = cloud(xyz, [(1, 2, 3)])
    big.is_bigendian = True
    seeds["big_endian"] = big
    return {name: serialize(msg) for name, msg in seeds.items()}


def camera_info(width, height, tx, hfov_deg=60.0):
    fx = width / 2.0 / math.tan(math.radians(hfov_deg) / 2.0)
    cx, cy = width / 2.0, height / 2.0
    info = CameraInfo()
    info.header.frame_id = "stereo_left_optical"
    info.width, info.height = width, height
    info.distortion_model = "plumb_bob"
    info.D = [0.0] * 5
    info.K = [fx, 0, cx, 0, fx, cy, 0, 0, 1]
    info.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    info.P = [fx, 0, cx, -fx * tx, 0, fx, cy, 0, 0, 0, 1, 0]
    return info


def mono8(width, height, shift, seed, seq=0, encoding="mono8", step=None):
    rng = random.Random(seed)
    texture = [[rng.randrange(256) for _ in range(width + shift)] for _ in range(height)]
    image = Image()
    image.header.frame_id = "stereo_left_optical"
    image.header.seq = seq
    image.width, image.height = width, height
    image.encoding = encoding
    image.step = width if step is None else step
    rows = [bytes(texture[r][shift:shift + width]) for r in range(height)]
    image.data = b"".join(row + b"\0" * (image.step - width) for row in rows)
    return image


def stereo_input_seeds():
    seeds = {}
    w, h = 32, 24
    left, right = camera_info(w, h, 0.0), camera_info(w, h, 0.5)
    seeds["pair_block_matching"] = serialize(left, right, mono8(w, h, 0, 1), mono8(w, h, 3, 1))
    seeds["pair_semi_global"] = serialize(left, right, mono8(w, h, 0, 2, seq=1),
                                          mono8(w, h, 2, 2, seq=1))
    w2, h2 = 64, 48
    seeds["pair_64x48_padded_rows"] = serialize(
        camera_info(w2, h2, 0.0), camera_info(w2, h2, 0.5), mono8(w2, h2, 0, 3, step=70),
        mono8(w2, h2, 4, 3, step=70))
    no_p = camera_info(w, h, 0.0)
    no_p.P = [0.0] * 12
    seeds["info_without_projection"] = serialize(no_p, right, mono8(w, h, 0, 4),
                                                 mono8(w, h, 1, 4))
    seeds["infos_differ_in_size"] = serialize(left, camera_info(w2, h2, 0.5))
    seeds["images_rgb8"] = serialize(left, right, mono8(w, h, 0, 5, encoding="rgb8"),
                                     mono8(w, h, 0, 5, encoding="rgb8"))
    bad_step = mono8(w, h, 0, 6)
    bad_step.step = w - 1
    seeds["image_step_too_small"] = serialize(left, right, bad_step, mono8(w, h, 0, 6))
    seeds["images_smaller_than_infos"] = serialize(left, right, mono8(16, 12, 0, 7),
                                                   mono8(16, 12, 1, 7))
    return seeds


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    for target, seeds in (("point_cloud", point_cloud_seeds()),
                          ("stereo_input", stereo_input_seeds())):
        folder = os.path.join(sys.argv[1], target)
        os.makedirs(folder, exist_ok=True)
        for name, data in seeds.items():
            with open(os.path.join(folder, name + ".bin"), "wb") as f:
                f.write(data)
        print(f"{folder}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
