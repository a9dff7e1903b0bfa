#!/usr/bin/env python3
"""rostest: the fault-injection suite, short version. Each fault is injected into a generated bag
and replayed through the real launch/pipeline.launch by `fault_replay` (on a private master of its
own), and the cue stream must never guide on a guess:
  untrusted_cues == 0, s_to_unsure <= 0.5 s, extra_alerts == 0, and guidance comes back after."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest

PKG = "assistive_tactile"


class FaultSuite(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bag = rospy.get_param("~bag")
        cls.faults = rospy.get_param("~faults", "black saturated").split()
        cls.at = float(rospy.get_param("~at", 2.5))
        cls.duration = float(rospy.get_param("~for", 1.5))
        cls.rate = float(rospy.get_param("~rate", 0.5))
        cls.work = tempfile.mkdtemp(prefix="fault_suite_")
        cls.results = {}

    def replay(self, fault):
        cmd = ["rosrun", "assistive_sim", "fault_replay", self.bag, "--fault", fault, "--at", str(self.at),
               "--for", str(self.duration), "--rate", str(self.rate), "--keep", os.path.join(self.work, fault),
               "--clean-record", os.path.join(self.work, "clean.jsonl")]
        env = dict(os.environ)
        p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        print(p.stdout)
        self.assertEqual(p.returncode, 0, "fault_replay failed:\n" + p.stdout[-3000:])
        return json.loads(p.stdout.strip().splitlines()[-1])

    def check(self, fault):
        r = self.replay(fault)
        self.assertEqual(r["untrusted_cues"], 0, r)
        self.assertIsNotNone(r["s_to_unsure"], r)
        self.assertLessEqual(r["s_to_unsure"], 0.5, r)
        self.assertEqual(r["extra_alerts"], 0, r)
        self.assertIsNotNone(r["s_to_guidance_after"], r)

    def test_faults(self):
        """Every fault in ~faults, one replay each (a failure names the fault and its figures)."""
        self.assertTrue(self.faults, "~faults is empty")
        for fault in self.faults:
            with self.subTest(fault=fault):
                self.check(fault)


if __name__ == "__main__":
    rospy.init_node("test_fault_suite")
    rostest.rosrun(PKG, "fault_suite", FaultSuite, sys.argv)
