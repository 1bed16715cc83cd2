#!/usr/bin/python3
"""make fuzz: builds the libFuzzer targets (cmake/fuzz.cmake) in their own clang build directory
and runs each for a fixed time; writes BUILD/report.json.

Each target fuzz_<name> runs with -max_total_time=SECONDS, -rss_limit_mb=2048, -timeout=10 and
its dictionary test/fuzz/<name>.dict when there is one, on a working corpus BUILD/corpus/<name>
(the committed seeds, test/fuzz/corpus/<name>/ and test/fuzz/regressions/<name>/, copied in; what
the fuzzer adds stays there for the next run). Findings are written to BUILD/artifacts/<name>/
(crash-*, timeout-*, oom-*, leak-*), the fuzzer's output to BUILD/logs/<name>.log. UBSan reports
stop the target like a crash (halt_on_error); third-party leaks are suppressed, each with its
reason, in test/fuzz/lsan.supp.

report.json: {"targets": [{"name", "seconds", "execs", "crashes", "timeouts", "ooms"}]} with
execs from libFuzzer's final stats and the finding counts from the artifacts this run wrote
(leaks count as ooms). Exits 1 when any target found something (or did not run).
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ["cloud", "images", "hypotheses", "yolo_pose", "mesh", "config", "semap_bridge"]
KINDS = {"crashes": ("crash-",), "timeouts": ("timeout-",), "ooms": ("oom-", "leak-")}


def configure_and_build(build, jobs, targets):
    """Configures BUILD once (clang, SGT_FUZZ=ON, no -march=native, no tests) and builds each
    target with the libraries it links; the output goes to BUILD/build.log. Returns the targets
    that built."""
    env = dict(os.environ, CC="clang", CXX="clang++",
               PATH="/usr/bin:/bin:/usr/sbin:/sbin:" + os.environ.get("PATH", ""))
    build.mkdir(parents=True, exist_ok=True)
    print("fuzz: building %d targets in %s (log: %s)" % (len(targets), build, build / "build.log"), flush=True)
    with open(build / "build.log", "w") as log:
        if not (build / "CMakeCache.txt").exists():
            cmd = ["cmake", "-S", str(ROOT), "-B", str(build), "-DSGT_FUZZ=ON", "-DSGT_NATIVE=OFF",
                   "-DCMAKE_BUILD_TYPE=RelWithDebInfo", "-DCATKIN_ENABLE_TESTING=OFF",
                   "-DCATKIN_DEVEL_PREFIX=%s" % (build / "devel")]
            if subprocess.run(cmd, env=env, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
                sys.exit("fuzz: configuring %s failed, see %s" % (build, build / "build.log"))
        built = []
        for name in targets:
            cmd = ["cmake", "--build", str(build), "-j%d" % jobs, "--target", "scene_graph_tracker_fuzz_" + name]
            log.flush()
            if subprocess.run(cmd, env=env, stdout=log, stderr=subprocess.STDOUT).returncode == 0:
                built.append(name)
            else:
                print("fuzz %-13s does not build, see %s" % (name, build / "build.log"), flush=True)
    return built


def prepare_corpus(build, name):
    corpus = build / "corpus" / name
    corpus.mkdir(parents=True, exist_ok=True)
    for kind in ("corpus", "regressions"):
        src = ROOT / "test" / "fuzz" / kind / name
        if src.is_dir():
            for f in sorted(src.iterdir()):
                if f.is_file():
                    shutil.copyfile(f, corpus / ("%s-%s" % (kind, f.name)))
    return corpus


def findings(artifacts, since):
    counts = {k: 0 for k in KINDS}
    for f in artifacts.iterdir():
        if f.stat().st_mtime < since:
            continue
        for kind, prefixes in KINDS.items():
            if f.name.startswith(prefixes):
                counts[kind] += 1
    return counts


def executions(log):
    m = re.findall(r"stat::number_of_executed_units:\s*(\d+)", log)
    if m:
        return int(m[-1])
    m = re.findall(r"^#(\d+)\s", log, re.MULTILINE)  # the last status line
    return int(m[-1]) if m else 0


def run(build, name, seconds):
    artifacts = build / "artifacts" / name
    artifacts.mkdir(parents=True, exist_ok=True)
    logs = build / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    corpus = prepare_corpus(build, name)
    cmd = [str(build / "bin" / ("fuzz_" + name)), "-max_total_time=%d" % seconds, "-rss_limit_mb=2048",
           "-timeout=10", "-print_final_stats=1", "-artifact_prefix=%s/" % artifacts]
    dictionary = ROOT / "test" / "fuzz" / (name + ".dict")
    if dictionary.exists():
        cmd.append("-dict=%s" % dictionary)
    cmd.append(str(corpus))
    env = dict(os.environ,
               UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1",
               ASAN_OPTIONS="detect_leaks=1",
               LSAN_OPTIONS="suppressions=%s:print_suppressions=0" % (ROOT / "test" / "fuzz" / "lsan.supp"))
    start = time.time()
    with open(logs / (name + ".log"), "w") as out:
        rc = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, cwd=build).returncode
    elapsed = time.time() - start
    log = (logs / (name + ".log")).read_text(errors="replace")
    entry = {"name": name, "seconds": round(elapsed), "execs": executions(log)}
    entry.update(findings(artifacts, start - 1))
    return entry, rc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(ROOT / "build" / "fuzz"), help="the fuzz build directory")
    ap.add_argument("--seconds", type=int, default=60, help="per target (FUZZ_SECONDS)")
    ap.add_argument("--jobs", type=int, default=2, help="build jobs")
    ap.add_argument("--targets", nargs="*", default=TARGETS, choices=TARGETS)
    args = ap.parse_args()
    build = Path(args.build).resolve()
    built = configure_and_build(build, args.jobs, args.targets)
    report, failed = [], len(built) < len(args.targets)
    for name in built:
        entry, rc = run(build, name, args.seconds)
        report.append(entry)
        found = entry["crashes"] + entry["timeouts"] + entry["ooms"]
        note = ""
        if found:
            note = " -> %s" % (build / "artifacts" / name)
        elif rc != 0:
            note = " -> fuzzer exited with %d, no artifact (see %s)" % (rc, build / "logs" / (name + ".log"))
        print("fuzz %-13s %4d s %10d execs  %d crashes  %d timeouts  %d ooms%s" %
              (name, entry["seconds"], entry["execs"], entry["crashes"], entry["timeouts"],
               entry["ooms"], note), flush=True)
        failed |= bool(found) or rc != 0
        (build / "report.json").write_text(json.dumps({"targets": report}, indent=2) + "\n")
    print("fuzz: report in %s" % (build / "report.json"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
