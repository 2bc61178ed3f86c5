#!/usr/bin/python3
"""Turns a folder in the TUM RGB-D layout into a bag with the official TUM topics, so any TUM
sequence on disk (or one written by `hope_synth --sequence`) replays like the real bags:

  /camera/depth/image        sensor_msgs/Image 32FC1, metres
  /camera/depth/camera_info  sensor_msgs/CameraInfo
  /camera/rgb/image_color    sensor_msgs/Image rgb8 (when rgb.txt is present)
  /camera/rgb/camera_info    sensor_msgs/CameraInfo
  /imu                       sensor_msgs/Imu from accelerometer.txt (no orientation:
                             orientation_covariance[0] = -1), when present
  /tf                        world -> openni_rgb_optical_frame from groundtruth.txt, when present

usage: tum_to_bag.py FOLDER OUT.bag [--intrinsics "fx fy cx cy"] [--depth-scale 5000]
The intrinsics are, in this order: --intrinsics, FOLDER/intrinsics.txt ("fx fy cx cy", as
hope_synth --sequence writes it), TUM freiburg1's (517.3 516.5 318.6 255.3); the script says
which it uses. Each topic's messages are numbered (header.seq) from 0, as a driver numbers them.
TUM's depth images are registered to the colour camera, so both use the colour camera's
optical frame. TUM's accelerometer.txt is read as the specific force in that frame."""

import argparse
import math
import os
import sys

import cv2
import rosbag
import rospy
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import CameraInfo, Image, Imu
from tf2_msgs.msg import TFMessage

FRAME = "openni_rgb_optical_frame"


def read_lines(path, fields):
    """(stamp, [values…]) per data line of a TUM text file; '#' lines are comments."""
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            parts = line.split()
            if len(parts) < fields:
                sys.exit("%s:%d: expected %d fields, got '%s'" % (path, number, fields, line))
            rows.append((float(parts[0]), parts[1:fields]))
    return rows


TUM_FREIBURG1 = [517.3, 516.5, 318.6, 255.3]


def intrinsics(args):
    """(fx fy cx cy, where they come from): --intrinsics, FOLDER/intrinsics.txt, TUM fr1."""
    if args.intrinsics is not None:
        text, source = args.intrinsics, "--intrinsics"
    else:
        path = os.path.join(args.folder, "intrinsics.txt")
        if not os.path.exists(path):
            return TUM_FREIBURG1, "TUM freiburg1's (no %s; give --intrinsics)" % path
        lines = [line for line in open(path).read().splitlines()
                 if line.strip() and not line.strip().startswith("#")]
        if len(lines) != 1:
            sys.exit("%s: expected one line \"fx fy cx cy\", found %d" % (path, len(lines)))
        text, source = lines[0], path
    try:
        k = [float(v) for v in text.split()]
    except ValueError:
        k = []
    if len(k) != 4 or not all(math.isfinite(v) for v in k) or k[0] <= 0 or k[1] <= 0:
        sys.exit("%s: intrinsics must be four finite numbers fx fy cx cy with fx, fy > 0, "
                 "got '%s'" % (source, text))
    return k, source


def camera_info(stamp, width, height, k, seq):
    info = CameraInfo()
    info.header.seq = seq
    info.header.stamp = stamp
    info.header.frame_id = FRAME
    info.width, info.height = width, height
    fx, fy, cx, cy = k
    info.distortion_model = "plumb_bob"
    info.D = [0.0] * 5
    info.K = [fx, 0, cx, 0, fy, cy, 0, 0, 1]
    info.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    info.P = [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0]
    return info


def image(stamp, array, encoding, seq):
    msg = Image()
    msg.header.seq = seq
    msg.header.stamp = stamp
    msg.header.frame_id = FRAME
    msg.height, msg.width = array.shape[:2]
    msg.encoding = encoding
    msg.is_bigendian = 0
    msg.step = array.strides[0]
    msg.data = array.tobytes()
    return msg


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("bag")
    parser.add_argument("--intrinsics", default=None,
                        help="fx fy cx cy (default: FOLDER/intrinsics.txt, else TUM fr1's)")
    parser.add_argument("--depth-scale", type=float, default=5000.0)
    args = parser.parse_args()
    k, source = intrinsics(args)
    print("tum_to_bag: intrinsics %s from %s" % (" ".join("%g" % v for v in k), source))
    depth_list = os.path.join(args.folder, "depth.txt")
    if not os.path.exists(depth_list):
        sys.exit("%s: no depth.txt (not a TUM RGB-D folder)" % args.folder)

    with rosbag.Bag(args.bag, "w") as bag:
        frames = 0
        for stamp, (name,) in read_lines(depth_list, 2):
            raw = cv2.imread(os.path.join(args.folder, name), cv2.IMREAD_ANYDEPTH)
            if raw is None:
                sys.exit("cannot read %s" % os.path.join(args.folder, name))
            metres = raw.astype("float32") / args.depth_scale
            metres[raw == 0] = float("nan")
            t = rospy.Time.from_sec(stamp)
            bag.write("/camera/depth/image", image(t, metres, "32FC1", frames), t)
            bag.write("/camera/depth/camera_info",
                      camera_info(t, metres.shape[1], metres.shape[0], k, frames), t)
            frames += 1
        rgb_list = os.path.join(args.folder, "rgb.txt")
        if os.path.exists(rgb_list):
            for seq, (stamp, (name,)) in enumerate(read_lines(rgb_list, 2)):
                bgr = cv2.imread(os.path.join(args.folder, name), cv2.IMREAD_COLOR)
                if bgr is None:
                    sys.exit("cannot read %s" % os.path.join(args.folder, name))
                t = rospy.Time.from_sec(stamp)
                bag.write("/camera/rgb/image_color",
                          image(t, cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), "rgb8", seq), t)
                bag.write("/camera/rgb/camera_info",
                          camera_info(t, bgr.shape[1], bgr.shape[0], k, seq), t)
        accelerometer = os.path.join(args.folder, "accelerometer.txt")
        if os.path.exists(accelerometer):
            for seq, (stamp, values) in enumerate(read_lines(accelerometer, 4)):
                imu = Imu()
                imu.header.seq = seq
                imu.header.stamp = rospy.Time.from_sec(stamp)
                imu.header.frame_id = FRAME
                imu.orientation_covariance[0] = -1.0
                imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z = (
                    float(v) for v in values)
                bag.write("/imu", imu, imu.header.stamp)
        groundtruth = os.path.join(args.folder, "groundtruth.txt")
        if os.path.exists(groundtruth):
            for stamp, values in read_lines(groundtruth, 8):
                tx, ty, tz, qx, qy, qz, qw = (float(v) for v in values)
                tf = TransformStamped()
                tf.header.stamp = rospy.Time.from_sec(stamp)
                tf.header.frame_id = "world"
                tf.child_frame_id = FRAME
                tf.transform.translation.x, tf.transform.translation.y = tx, ty
                tf.transform.translation.z = tz
                tf.transform.rotation.x, tf.transform.rotation.y = qx, qy
                tf.transform.rotation.z, tf.transform.rotation.w = qz, qw
                bag.write("/tf", TFMessage(transforms=[tf]), tf.header.stamp)
    print("tum_to_bag: wrote %d depth frames of %s to %s" % (frames, args.folder, args.bag))


if __name__ == "__main__":
    main()
