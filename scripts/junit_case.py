"""Writes one JUnit test case (for catkin's run_tests and scripts/test_summary.py) from the result
of a check script: passed, or failed with the message in a file.

Usage: python3 junit_case.py OUT.xml SUITE CASE [FAILURE_FILE]   (FAILURE_FILE given and not empty: failed)
"""
import os
import sys
import xml.etree.ElementTree as ET


def main():
    if len(sys.argv) not in (4, 5):
        sys.stderr.write(__doc__)
        return 2
    path, suite_name, case_name = sys.argv[1:4]
    message = ""
    if len(sys.argv) == 5 and os.path.exists(sys.argv[4]):
        with open(sys.argv[4], errors="replace") as fh:
            message = fh.read().strip()
    suite = ET.Element("testsuite", name=suite_name, tests="1", failures="1" if message else "0", errors="0")
    case = ET.SubElement(suite, "testcase", classname=suite_name, name=case_name)
    if message:
        ET.SubElement(case, "failure", message=message.splitlines()[0]).text = message
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
