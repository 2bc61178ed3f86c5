#!/usr/bin/python3
"""hope's objects, and the surfaces they stand on, as MoveIt collision objects on
/collision_object (move_group's planning scene monitor reads it): one per object and per
supporting surface from each frame's /hope/objects and /hope/planes; what left view is removed.
Needs moveit_msgs (ROS Noetic has it, Debian 12 does not); collision_boxes() needs hope's only."""

from geometry_msgs.msg import Point, Pose, Quaternion

SLAB = 0.02  # m: a support surface as a slab this thick, its top at the surface's height


def collision_boxes(objects, planes):
    """(name, [x, y, z] box size, geometry_msgs/Pose of its centre) for each object (its upright
    box as hope gives it) and each plane an object stands on (a slab over the plane's x-y extent),
    in the messages' frame."""
    boxes = [("hope_object_%d" % o.index, list(o.box.dimensions), o.pose) for o in objects.objects]
    by_id = {p.id: p for p in planes.planes}
    for plane_id in sorted({o.plane_id for o in objects.objects} & set(by_id)):
        p = by_id[plane_id]
        centre = Point((p.x_min + p.x_max) / 2, (p.y_min + p.y_max) / 2, p.height - SLAB / 2)
        boxes.append(("hope_surface_%d" % p.id, [p.x_max - p.x_min, p.y_max - p.y_min, SLAB],
                      Pose(centre, Quaternion(0, 0, 0, 1))))
    return boxes


def main():
    import message_filters
    import rospy
    try:
        from moveit_msgs.msg import CollisionObject
    except ImportError:
        raise SystemExit("objects_to_moveit: needs moveit_msgs (ros-noetic-moveit-msgs on Noetic)")
    from shape_msgs.msg import SolidPrimitive
    from hope.msg import ObjectArray, PlaneArray
    rospy.init_node("hope_to_moveit")
    publisher = rospy.Publisher("/collision_object", CollisionObject, queue_size=100)
    shown = set()

    def on_frame(objects, planes):
        names = set()
        for name, size, pose in collision_boxes(objects, planes):
            box = SolidPrimitive(type=SolidPrimitive.BOX, dimensions=size)
            publisher.publish(CollisionObject(
                header=objects.header, id=name, primitives=[box], primitive_poses=[pose],
                operation=CollisionObject.ADD))
            names.add(name)
        for name in shown - names:
            publisher.publish(CollisionObject(header=objects.header, id=name,
                                              operation=CollisionObject.REMOVE))
        shown.clear()
        shown.update(names)

    inputs = [message_filters.Subscriber("/hope/objects", ObjectArray),
              message_filters.Subscriber("/hope/planes", PlaneArray)]
    message_filters.TimeSynchronizer(inputs, 10).registerCallback(on_frame)
    rospy.spin()


if __name__ == "__main__":
    main()
