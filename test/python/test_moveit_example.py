"""scripts/objects_to_moveit.py's conversion, without MoveIt: each object's upright box as hope
gives it (test_object_conversion checks that box against the object's points), and a slab
under each surface an object stands on, its top at the surface's height, over its extent."""

import importlib.util
import os
import unittest

from geometry_msgs.msg import Point, Pose, Quaternion
from hope.msg import Object, ObjectArray, Plane, PlaneArray
from shape_msgs.msg import SolidPrimitive

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "objects_to_moveit.py")
spec = importlib.util.spec_from_file_location("objects_to_moveit", SCRIPT)
example = importlib.util.module_from_spec(spec)
spec.loader.exec_module(example)


def standing(index, plane_id, centre, size):
    box = SolidPrimitive(type=SolidPrimitive.BOX, dimensions=size)
    return Object(index=index, plane_id=plane_id, box=box,
                  pose=Pose(Point(*centre), Quaternion(0, 0, 0.38268343, 0.92387953)))


class CollisionBoxes(unittest.TestCase):
    def test_objects_keep_their_boxes_and_their_table_becomes_a_slab_under_them(self):
        # The demo room's table (0.75 m up, x 1.3-2.2, y -0.9-0.1) with a book and a cone on it,
        # and a thing on plane 9, which this frame's planes do not hold.
        table = Plane(id=7, height=0.75, x_min=1.3, x_max=2.2, y_min=-0.9, y_max=0.1)
        floor = Plane(id=3, height=0.0, x_min=-1.0, x_max=4.0, y_min=-3.0, y_max=2.0)
        objects = ObjectArray(objects=[standing(0, 7, (1.825, -0.35, 0.775), [0.25, 0.2, 0.05]),
                                       standing(1, 7, (1.5, -0.2, 0.875), [0.2, 0.2, 0.25]),
                                       standing(2, 9, (3.0, 1.0, 0.5), [0.1, 0.1, 0.2])])
        boxes = {name: (size, pose) for name, size, pose in
                 example.collision_boxes(objects, PlaneArray(planes=[floor, table]))}
        self.assertEqual(sorted(boxes), ["hope_object_0", "hope_object_1", "hope_object_2",
                                         "hope_surface_7"],
                         "a slab for the table, none for the floor nothing stands on")
        for o in objects.objects:
            size, pose = boxes["hope_object_%d" % o.index]
            self.assertEqual(size, list(o.box.dimensions))
            self.assertEqual(pose, o.pose)
        size, pose = boxes["hope_surface_7"]
        self.assertAlmostEqual(pose.position.z + size[2] / 2, 0.75,
                               msg="its top at the table's height")
        self.assertAlmostEqual(pose.position.x - size[0] / 2, 1.3)
        self.assertAlmostEqual(pose.position.x + size[0] / 2, 2.2)
        self.assertAlmostEqual(pose.position.y - size[1] / 2, -0.9)
        self.assertAlmostEqual(pose.position.y + size[1] / 2, 0.1)
        self.assertEqual((pose.orientation.x, pose.orientation.y, pose.orientation.z,
                          pose.orientation.w), (0, 0, 0, 1))

    def test_no_object_no_collision_object(self):
        self.assertEqual(example.collision_boxes(ObjectArray(), PlaneArray(planes=[Plane(id=1)])),
                         [])


if __name__ == "__main__":
    unittest.main()
