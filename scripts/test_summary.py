#!/usr/bin/env python3
"""Summarise gtest/rostest JUnit results and gate on them.

Usage: test_summary.py RESULTS_DIR [RUN_TESTS_LOG] [--sanitizer-logs DIR]
Prints failing cases (with the tail of the log when results are missing), then exactly one
last line `N passed, N failed` (plus `, N skipped` when some were skipped). Exit status 1 when
any case failed, when catkin_test_results disagrees, or when there are no results at all.
--sanitizer-logs (make test-asan, make test-tsan): the directory the sanitized processes write
their reports to (log_path); one more case, "sanitizer reports", fails when it holds any file
(the first lines of each are printed), even when every test passed. A file that holds only
LeakSanitizer's own crash at a process's exit (see tool_failure) is printed as a sanitizer tool
failure and counted on the last line, not as a report.

  test_summary.py --tool-failure FILE   exit status 0 when FILE is such a tool failure
"""
import os
import re
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
            # The text holds the whole failure; the message attribute is often its first line only.
            yield (name, (bad.text or bad.get("message") or "").strip(), "failed")
        elif case.find("skipped") is not None or case.get("result") == "skipped":
            yield (name, "", "skipped")
        else:
            yield (name, "", "passed")


# What a sanitizer writes when it found a defect.
DEFECT = re.compile(r"ERROR: (AddressSanitizer|LeakSanitizer: detected)|runtime error:|"
                    r"WARNING: ThreadSanitizer|SUMMARY: (Address|Leak|Thread|UndefinedBehavior)")


def tool_failure(text):
    """Whether a sanitizer log holds only LeakSanitizer's stop-the-world tracer crashing at exit
    ("Tracer caught signal 11 ... LeakSanitizer has encountered a fatal error"): an intermittent
    failure of the runtime itself (google/sanitizers#1353), after which that process's leaks
    were not checked. It is no finding about the code, and is shown as what it is."""
    return "LeakSanitizer has encountered a fatal error" in text and not DEFECT.search(text)


def sanitizer_reports(directory, lines=40):
    """(path, first lines) of each sanitizer report file in directory."""
    reports = []
    if not os.path.isdir(directory):
        return reports
    for f in sorted(os.listdir(directory)):
        path = os.path.join(directory, f)
        with open(path, errors="replace") as fh:
            head = fh.readlines()
        text = "".join(head[:lines]) + ("    ... (%d lines)\n" % len(head) if len(head) > lines else "")
        reports.append((path, text, tool_failure("".join(head))))
    return reports


def main():
    args = sys.argv[1:]
    if args[:1] == ["--tool-failure"]:
        with open(args[1], errors="replace") as fh:
            return 0 if tool_failure(fh.read()) else 1
    sanitizer_logs = None
    if "--sanitizer-logs" in args:
        i = args.index("--sanitizer-logs")
        sanitizer_logs = args[i + 1]
        del args[i:i + 2]
    results = args[0]
    log = args[1] if len(args) > 1 else None
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    failures = []
    for top, _, files in os.walk(results):
        for f in sorted(files):
            if f.endswith(".xml"):
                for name, msg, status in cases(os.path.join(top, f)):
                    counts[status] += 1
                    if status == "failed":
                        failures.append((name, msg))
    logs = sanitizer_reports(sanitizer_logs) if sanitizer_logs else []
    reports = [(path, text) for path, text, tool in logs if not tool]
    tool_failures = [(path, text) for path, text, tool in logs if tool]
    gate = subprocess.run(["catkin_test_results", results], capture_output=True, text=True)
    for name, msg in failures:
        print("FAILED %s\n    %s" % (name, msg.replace("\n", "\n    ")[:2000]))
    if gate.returncode != 0 and not failures:
        print(gate.stdout + gate.stderr)
        counts["failed"] += 1
    for k, (path, text) in enumerate(reports):
        if k < 10:
            print("SANITIZER REPORT %s\n    %s" % (path, text.rstrip().replace("\n", "\n    ")))
        else:
            print("SANITIZER REPORT %s" % path)
    for path, text in tool_failures:
        print("SANITIZER TOOL FAILURE %s (LeakSanitizer crashed at exit: that process's leaks were "
              "not checked)\n    %s" % (path, text.rstrip().replace("\n", "\n    ")))
    if sum(counts.values()) == 0:
        print("no test results found in %s" % results)
        counts["failed"] += 1
    if sanitizer_logs:
        counts["failed" if reports else "passed"] += 1
        if reports:
            print("FAILED sanitizer reports: %d file(s) in %s" % (len(reports), sanitizer_logs))
    if counts["failed"] and log and os.path.exists(log):
        print("---- tail of %s ----" % log)
        with open(log, errors="replace") as fh:
            print("".join(fh.readlines()[-40:]))
    line = "%d passed, %d failed" % (counts["passed"], counts["failed"])
    if counts["skipped"]:
        line += ", %d skipped" % counts["skipped"]
    if tool_failures:
        line += ", %d sanitizer tool failure%s" % (len(tool_failures), "s" if len(tool_failures) > 1 else "")
    print(line)
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
