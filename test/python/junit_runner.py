"""Runs a unittest TestCase class and, with --xml=PATH among the arguments, writes a JUnit result
for catkin's run_tests (make test). Shared by the Python tests in this directory."""
import os
import sys
import time
import unittest
import xml.etree.ElementTree as ET


def argument(name):
    """The value of --name=VALUE among the command-line arguments, or None."""
    return next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith(f"--{name}=")), None)


def write_junit(suite_name, result, cases, seconds, path):
    suite = ET.Element("testsuite", name=suite_name, tests=str(len(cases)), time=f"{seconds:.3f}",
                       failures=str(len(result.failures)), errors=str(len(result.errors)))
    bad = {id(t): ("failure", msg) for t, msg in result.failures}
    bad.update({id(t): ("error", msg) for t, msg in result.errors})
    for case in cases:
        el = ET.SubElement(suite, "testcase", classname=type(case).__name__, name=case._testMethodName)
        if id(case) in bad:
            kind, msg = bad[id(case)]
            ET.SubElement(el, kind, message=msg.strip().splitlines()[-1]).text = msg
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main(suite_name, *case_classes):
    """Runs the tests of case_classes; exits 0 when all pass."""
    xml = argument("xml")  # read before the tests run: a test may patch sys.argv
    cases = [c for k in case_classes for c in unittest.defaultTestLoader.loadTestsFromTestCase(k)]
    start = time.time()
    result = unittest.TextTestRunner(verbosity=2).run(unittest.TestSuite(cases))
    if xml:
        write_junit(suite_name, result, cases, time.time() - start, xml)
    sys.exit(0 if result.wasSuccessful() else 1)
