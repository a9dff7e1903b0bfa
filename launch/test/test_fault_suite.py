#!/usr/bin/env python3
"""rostest: the fault-injection suite, short version. Each fault is injected into a generated bag
and replayed through the real launch/pipeline.launch by `fault_replay` (on a private master of its
own), and the cue stream must never guide on a guess:
  untrusted_cues == 0, s_to_unsure <= 0.5 s, extra_alerts == 0, and guidance comes back after;
and the obstacle stage reports no mover on a world without people (movers_confirmed_per_frame 0).
One test case per fault (test_black, test_gap, ...), so a failure names the fault and its figures.

The replays run `~jobs` at a time (default 2: each pipeline plays at half speed and needs well
under one core), the first fault's replay writing the clean run's record that the others reuse.
The faulted bags are deleted at the end unless `~keep` names a folder to keep them in."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from concurrent.futures import ThreadPoolExecutor

import rospy
import rostest

PKG = "assistive_bringup"
ALL_FAULTS = ("black", "saturated", "frozen", "gap", "loop", "desync", "nan_info", "size")


class FaultSuite(unittest.TestCase):
    faults = []
    results = {}

    @classmethod
    def setUpClass(cls):
        cls.bag = rospy.get_param("~bag")
        cls.at = float(rospy.get_param("~at", 4.0))
        cls.duration = float(rospy.get_param("~for", 1.5))
        cls.rate = float(rospy.get_param("~rate", 0.5))
        cls.jobs = max(1, int(rospy.get_param("~jobs", 2)))
        # The faulted bags (~75 MB each) go to a temporary folder removed at the end, or to ~keep.
        cls.keep = rospy.get_param("~keep", "")
        if cls.keep:
            os.makedirs(cls.keep, exist_ok=True)
        cls.work = cls.keep or tempfile.mkdtemp(prefix="fault_suite_")
        cls.clean = os.path.join(cls.work, "clean.jsonl")
        lock = threading.Lock()

        def run(fault, wait_for_clean):
            if wait_for_clean:
                until = time.time() + 600
                while not os.path.isfile(cls.clean) and time.time() < until:
                    time.sleep(0.5)
            t0 = time.time()
            cmd = ["rosrun", "assistive_sim", "fault_replay", cls.bag, "--fault", fault, "--at", str(cls.at),
                   "--for", str(cls.duration), "--rate", str(cls.rate), "--keep", os.path.join(cls.work, fault),
                   "--clean-record", cls.clean]
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
            with lock:
                print("== %s (%.0f s) ==\n%s" % (fault, time.time() - t0, p.stdout), flush=True)
            return p.returncode, p.stdout

        with ThreadPoolExecutor(max_workers=cls.jobs) as ex:
            futures = {f: ex.submit(run, f, i > 0) for i, f in enumerate(cls.faults)}
            cls.results = {f: fut.result() for f, fut in futures.items()}

    @classmethod
    def tearDownClass(cls):
        if not cls.keep:
            shutil.rmtree(cls.work, ignore_errors=True)

    def check(self, fault):
        rc, out = self.results[fault]
        self.assertEqual(rc, 0, "fault_replay failed:\n" + out[-3000:])
        r = json.loads(out.strip().splitlines()[-1])
        table = "\n" + "\n".join(l for l in out.splitlines() if l.startswith(("fault ", "  ")))
        self.assertEqual(r["untrusted_cues"], 0, table)
        self.assertIsNotNone(r["s_to_unsure"], table)
        self.assertGreaterEqual(r["s_to_unsure"], 0.0, table)
        self.assertLessEqual(r["s_to_unsure"], 0.5, table)
        self.assertEqual(r["extra_alerts"], 0, table)
        self.assertIsNotNone(r["s_to_guidance_after"], table)
        self.assertGreaterEqual(r["s_to_guidance_after"], 0.0, table)
        if r.get("false_crossing_cues") is not None:  # a world without people
            self.assertEqual(r["movers_confirmed_per_frame"], 0.0, table)
            self.assertEqual(r["false_crossing_cues"], 0, table)


def add_fault_tests(faults):
    for fault in faults:
        if fault not in ALL_FAULTS:
            raise ValueError("unknown fault %r (known: %s)" % (fault, " ".join(ALL_FAULTS)))
        setattr(FaultSuite, "test_%s" % fault, lambda self, f=fault: self.check(f))
    FaultSuite.faults = list(faults)


if __name__ == "__main__":
    rospy.init_node("test_fault_suite")
    faults = rospy.get_param("~faults", " ".join(ALL_FAULTS)).split()
    if not faults:
        raise SystemExit("~faults is empty")
    add_fault_tests(faults)
    rostest.rosrun(PKG, "fault_suite", FaultSuite, sys.argv)
