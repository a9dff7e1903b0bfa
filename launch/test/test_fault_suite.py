#!/usr/bin/env python3
"""rostest: the fault-injection suite, short version. Each fault is injected into a generated bag
and replayed through the real launch/pipeline.launch by `fault_replay` (on a private master of its
own), and the cue stream must never guide on a guess:
  untrusted_cues == 0, s_to_unsure <= 0.5 s, extra_alerts == 0, and guidance comes back after.
One test case per fault (test_black, test_gap, ...), so a failure names the fault and its figures."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest

PKG = "assistive_bringup"
ALL_FAULTS = ("black", "saturated", "frozen", "gap", "loop", "desync", "nan_info", "size")


class FaultSuite(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bag = rospy.get_param("~bag")
        cls.at = float(rospy.get_param("~at", 4.0))
        cls.duration = float(rospy.get_param("~for", 1.5))
        cls.rate = float(rospy.get_param("~rate", 0.5))
        cls.work = tempfile.mkdtemp(prefix="fault_suite_")

    def replay(self, fault):
        cmd = ["rosrun", "assistive_sim", "fault_replay", self.bag, "--fault", fault, "--at", str(self.at),
               "--for", str(self.duration), "--rate", str(self.rate), "--keep", os.path.join(self.work, fault),
               "--clean-record", os.path.join(self.work, "clean.jsonl")]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        print(p.stdout)
        self.assertEqual(p.returncode, 0, "fault_replay failed:\n" + p.stdout[-3000:])
        return json.loads(p.stdout.strip().splitlines()[-1]), p.stdout

    def check(self, fault):
        r, out = self.replay(fault)
        table = "\n" + "\n".join(l for l in out.splitlines() if l.startswith(("fault ", "  ")))
        self.assertEqual(r["untrusted_cues"], 0, table)
        self.assertIsNotNone(r["s_to_unsure"], table)
        self.assertLessEqual(r["s_to_unsure"], 0.5, table)
        self.assertEqual(r["extra_alerts"], 0, table)
        self.assertIsNotNone(r["s_to_guidance_after"], table)


def add_fault_tests(faults):
    for fault in faults:
        if fault not in ALL_FAULTS:
            raise ValueError("unknown fault %r (known: %s)" % (fault, " ".join(ALL_FAULTS)))
        setattr(FaultSuite, "test_%s" % fault, lambda self, f=fault: self.check(f))


if __name__ == "__main__":
    rospy.init_node("test_fault_suite")
    faults = rospy.get_param("~faults", " ".join(ALL_FAULTS)).split()
    if not faults:
        raise SystemExit("~faults is empty")
    add_fault_tests(faults)
    rostest.rosrun(PKG, "fault_suite", FaultSuite, sys.argv)
