#!/usr/bin/python3
"""The test summary's sanitizer gate (scripts/test_summary.py): a report fails the run, and
LeakSanitizer's own crash at exit is shown as a tool failure instead.

  /usr/bin/python3 test/python/test_test_summary.py [--xml=RESULT.xml]
"""
import contextlib
import io
import os
import sys
import tempfile
import unittest
from unittest import mock

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'scripts'))
import junit_runner  # noqa: E402
import test_summary  # noqa: E402

TRACER_CRASH = """Tracer caught signal 11: addr=0x34f8 pc=0x7fd0dc4e80f0 sp=0x7fd0d5bfed10
==31329==LeakSanitizer has encountered a fatal error.
==31329==HINT: For debugging, try setting environment variable LSAN_OPTIONS=verbosity=1:log_threads=1
==31329==HINT: LeakSanitizer does not work under ptrace (strace, gdb, etc)
"""
OVERFLOW = """=================================================================
==4711==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x602000000014
READ of size 4 at 0x602000000014 thread T0
SUMMARY: AddressSanitizer: heap-buffer-overflow cloud.cpp:42 in rangesFromCloud
"""
LEAK = """==12==ERROR: LeakSanitizer: detected memory leaks
Direct leak of 40 byte(s) in 1 object(s) allocated from:
SUMMARY: AddressSanitizer: 40 byte(s) leaked in 1 allocation(s).
"""
UB = "frame.cpp:10:5: runtime error: signed integer overflow\n"
JUNIT = ('<testsuite tests="1"><testcase classname="Suite" name="passes" status="run"/>'
         '</testsuite>')


class TestSummaryTest(unittest.TestCase):
    def test_only_the_tracer_crash_is_a_tool_failure(self):
        self.assertTrue(test_summary.tool_failure(TRACER_CRASH))
        for report in (OVERFLOW, LEAK, UB, TRACER_CRASH + UB, LEAK + TRACER_CRASH):
            self.assertFalse(test_summary.tool_failure(report), report)

    def run_summary(self, logs):
        with tempfile.TemporaryDirectory() as d:
            results, sanitizer = os.path.join(d, 'results'), os.path.join(d, 'sanitizer')
            os.makedirs(results), os.makedirs(sanitizer)
            with open(os.path.join(results, 'gtest-x.xml'), 'w') as f:
                f.write(JUNIT)
            for k, text in enumerate(logs):
                with open(os.path.join(sanitizer, 'asan.nodelet.%d' % k), 'w') as f:
                    f.write(text)
            out = io.StringIO()
            argv = ['test_summary.py', results, '--sanitizer-logs', sanitizer]
            with mock.patch.object(sys, 'argv', argv), contextlib.redirect_stdout(out):
                status = test_summary.main()
            return status, out.getvalue().strip().splitlines()[-1]

    def test_a_report_fails_the_run_and_a_tool_failure_is_counted(self):
        self.assertEqual(self.run_summary([]), (0, '2 passed, 0 failed'))
        self.assertEqual(self.run_summary([TRACER_CRASH]),
                         (0, '2 passed, 0 failed, 1 sanitizer tool failure'))
        self.assertEqual(self.run_summary([OVERFLOW, TRACER_CRASH]),
                         (1, '1 passed, 1 failed, 1 sanitizer tool failure'))


if __name__ == '__main__':
    junit_runner.main('test_summary', TestSummaryTest)
