"""HoPE, the horizontal plane extractor, from Python.

    import numpy as np, hope
    extractor = hope.Extractor(r_xy=0.05, r_z=0.02)
    result = extractor.extract(points, quaternion=(qx, qy, qz, qw))  # N x 3 or H x W x 3
    result = extractor.extract(points, level=True)  # no IMU: up from the scene
    for plane in result.planes:
        print(plane.id, plane.height, plane.area)
    result.labels  # per point: index into result.planes, -1 for none

A stream, with the nodelet's and hope_extract --sequence's policy (persistent ids, objects,
an accelerometer averaged over a window, up from the scene smoothed and held):

    pipeline = hope.Pipeline(levelling="off")  # tracking_mode "auto": odometry for gravity
    for stamp, points, gravity in frames:
        frame = pipeline.process(points, stamp, gravity=gravity)
        print([(p.id, p.height) for p in frame.planes], len(frame.objects))

    points = hope.read_cloud("scene.pcd")  # .pcd (any encoding) or .ply, as hope_extract reads

The C++ core does the work (the GIL is released meanwhile); float32 arrays whose points are
evenly spaced in memory are read in place. hope.msg holds the ROS messages.
"""

from hope._hope import (  # noqa: F401  (re-exported)
    Extractor,
    ExtractionResult,
    LevellingError,
    Pipeline,
    Plane,
    PlaneTracker,
    SurfaceMap,
    TrackEvent,
    depth_to_cloud,
    parameters,
    plane_color,
    read_cloud,
)

__all__ = [
    "Extractor",
    "ExtractionResult",
    "LevellingError",
    "Pipeline",
    "Plane",
    "PlaneTracker",
    "SurfaceMap",
    "TrackEvent",
    "depth_to_cloud",
    "parameters",
    "plane_color",
    "read_cloud",
]
