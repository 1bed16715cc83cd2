#!/usr/bin/env python3
"""rostest node of failed_start.test: loads a tracker nodelet whose static map does not exist into
a running manager (the load fails), then asks the manager for its nodelets and loads a detector
nodelet (without a model it stays up, disabled). Before the tracker shut its subscriptions down on
a failed start, the manager died in the first call (SIGSEGV)."""
import sys
import unittest

import rospy
import rostest
from nodelet.srv import NodeletList, NodeletLoad


class FailedStartTest(unittest.TestCase):
    def load(self, name, kind):
        rospy.wait_for_service("/manager/load_nodelet", 60.0)
        return rospy.ServiceProxy("/manager/load_nodelet", NodeletLoad)(
            name=name, type=kind, remap_source_args=[], remap_target_args=[], my_argv=[], bond_id="")

    def test_the_manager_survives_a_nodelet_that_cannot_start(self):
        rospy.set_param("/tracker/static_map", "/nonexistent/static_map.ply")
        with self.assertRaises(rospy.ServiceException):  # the manager answers a failed load so
            self.load("/tracker", "scene_graph_tracker/TrackerNodelet")
        rospy.wait_for_service("/manager/list", 10.0)
        self.assertEqual(rospy.ServiceProxy("/manager/list", NodeletList)().nodelets, [])
        rospy.set_param("/detector/model", "/nonexistent/model.yaml")
        self.assertTrue(self.load("/detector", "scene_graph_tracker/DetectorNodelet").success)
        self.assertEqual(rospy.ServiceProxy("/manager/list", NodeletList)().nodelets, ["/detector"])


if __name__ == "__main__":
    rospy.init_node("failed_start_check")
    rostest.rosrun("scene_graph_tracker", "failed_start_check", FailedStartTest, sys.argv)
