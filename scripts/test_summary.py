#!/usr/bin/env python3
"""Summarise gtest/rostest JUnit results and gate on them.

Usage: test_summary.py RESULTS_DIR [RUN_TESTS_LOG]
Prints failing cases (with the tail of the log when results are missing), then exactly one
last line `N passed, N failed` (plus `, N skipped` when some were skipped). Exit status 1 when
any case failed, when catkin_test_results disagrees, or when there are no results at all.
"""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET


def cases(path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        yield (os.path.basename(path), "unparsable result file: %s" % err, "failed")
        return
    for case in root.iter("testcase"):
        name = "%s.%s" % (case.get("classname", "?"), case.get("name", "?"))
        bad = case.find("failure")
        if bad is None:
            bad = case.find("error")
        if bad is not None:
            yield (name, (bad.get("message") or bad.text or "").strip(), "failed")
        elif case.find("skipped") is not None or case.get("result") == "skipped":
            yield (name, "", "skipped")
        else:
            yield (name, "", "passed")


def main():
    results = sys.argv[1]
    log = sys.argv[2] if len(sys.argv) > 2 else None
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    failures = []
    for top, _, files in os.walk(results):
        for f in sorted(files):
            if f.endswith(".xml"):
                for name, msg, status in cases(os.path.join(top, f)):
                    counts[status] += 1
                    if status == "failed":
                        failures.append((name, msg))
    gate = subprocess.run(["catkin_test_results", results], capture_output=True, text=True)
    for name, msg in failures:
        print("FAILED %s\n    %s" % (name, msg.replace("\n", "\n    ")[:2000]))
    if gate.returncode != 0 and not failures:
        print(gate.stdout + gate.stderr)
        counts["failed"] += 1
    if sum(counts.values()) == 0:
        print("no test results found in %s" % results)
        counts["failed"] += 1
    if counts["failed"] and log and os.path.exists(log):
        print("---- tail of %s ----" % log)
        with open(log, errors="replace") as fh:
            print("".join(fh.readlines()[-40:]))
    line = "%d passed, %d failed" % (counts["passed"], counts["failed"])
    if counts["skipped"]:
        line += ", %d skipped" % counts["skipped"]
    print(line)
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
