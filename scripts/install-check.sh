#!/usr/bin/env bash
# make install-check (part of `make test`): the package as an install space, without its sources.
#  1. `cmake --install BUILD --prefix TMP/install`.
#  2. No installed program, library, launch or config file names the source tree.
#  3. The tracker's rostest runs from the install space: its test program and launch file are
#     copied into the prefix, its map files into TMP, and the environment holds only the prefix
#     and /usr. It runs in a mount namespace where an empty tmpfs covers the source tree (the
#     build directory with it), so a compiled-in source path fails loudly. Without mount
#     namespaces (no root, no user namespaces) it runs anyway and says so.
# Exits 1 on a failure; with --xml=RESULT.xml also writes the JUnit case install.check.
#   scripts/install-check.sh BUILD [--xml=RESULT.xml]
set -uo pipefail
export PATH=/usr/bin:/bin:$PATH
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="" xml=""
for a in "$@"; do
  case "$a" in
    --xml=*) xml="${a#--xml=}" ;;
    -*) echo "usage: $0 BUILD [--xml=RESULT.xml]" >&2; exit 2 ;;
    *) build="$(cd "$a" && pwd)" ;;
  esac
done
[ -n "$build" ] || { echo "usage: $0 BUILD [--xml=RESULT.xml]" >&2; exit 2; }
tmp="$(mktemp -d /tmp/sgt-install-check.XXXXXX)"
report="$tmp/report"
: > "$report"
trap '[ -n "${SGT_KEEP_TMP:-}" ] || rm -rf "$tmp"' EXIT
prefix="$tmp/install"
pkg=scene_graph_tracker

fail() { echo "$*" | tee -a "$report" >&2; }

finish() {
  [ -n "$xml" ] && /usr/bin/python3 "$root/scripts/junit_case.py" "$xml" install check "$report"
  if [ -s "$report" ]; then echo "install-check: FAILED"; exit 1; fi
  echo "install-check: passed"
  exit 0
}

install_package() {
  if ! cmake --install "$build" --prefix "$prefix" > "$tmp/install.log" 2>&1; then
    fail "cmake --install $build failed:"$'\n'"$(tail -20 "$tmp/install.log")"
    finish
  fi
  echo "install-check: installed into $prefix ($(find "$prefix" -type f | wc -l) files)"
}

# Files that name the source tree: programs, libraries, launch, config, scripts. Python bytecode
# (catkin compiles the generated messages in the build tree) is left out. A sanitized build is
# not checked: its sanitizers keep the source file of every check in the binaries (reports name
# them), which no lookup at run time uses.
check_no_source_paths() {
  if [ -n "${SGT_SANITIZER_RUNTIME:-}" ]; then
    echo "install-check: sanitized build: source paths of the sanitizers' reports not checked"
    return
  fi
  local hits
  hits="$(grep -rlF --exclude='*.pyc' "$root/" "$prefix" | sed "s|^$prefix/||")"
  [ -z "$hits" ] || fail "installed files name the source tree $root:"$'\n'"$hits"
}

# The rostest's own files in the prefix and TMP: the test program, the launch file with the map
# paths moved out of the build directory, the nodelet wrapper of a sanitized build.
stage_rostest() {
  mkdir -p "$tmp/maps" "$prefix/share/$pkg/test"
  cp "$build"/test_maps/* "$tmp/maps/"
  cp "$build/devel/lib/$pkg/rostest_tracker" "$prefix/lib/$pkg/"
  sed "s|$build/test_maps|$tmp/maps|g" "$build/test/ros/tracker.test" > "$prefix/share/$pkg/test/tracker.test"
  if [ -n "${SGT_SANITIZER_RUNTIME:-}" ]; then
    mkdir -p "$prefix/lib/nodelet" "$tmp/sanitizers" "$tmp/sanitizer_logs"
    cp "$root/test/sanitizers/nodelet" "$prefix/lib/nodelet/nodelet"
    cp "$root"/test/sanitizers/*.supp "$tmp/sanitizers/"
  fi
}

# A sanitizer option string with its paths moved out of the hidden source tree: suppressions from
# TMP's copies, reports into TMP (collect_sanitizer_logs brings them back). A sanitizer that cannot
# read its suppressions or open its log stops the process at start.
relocated() {
  local v="${1//$root\/test\/sanitizers/$tmp/sanitizers}"
  echo "${v//$build\/sanitizer/$tmp/sanitizer_logs}"
}

# The reports of the install-space run go where the build's other reports are, so that
# test_summary.py counts them like any other.
collect_sanitizer_logs() {
  [ -n "${SGT_SANITIZER_RUNTIME:-}" ] || return 0
  local f
  for f in "$tmp"/sanitizer_logs/*; do
    [ -e "$f" ] || continue
    mkdir -p "$build/sanitizer"
    cp "$f" "$build/sanitizer/install-check.$(basename "$f")"
    if /usr/bin/python3 "$root/scripts/test_summary.py" --tool-failure "$f"; then
      echo "install-check: sanitizer tool failure (not a report): $build/sanitizer/install-check.$(basename "$f")"
    else
      fail "sanitizer report from the install-space run: $build/sanitizer/install-check.$(basename "$f")"
    fi
  done
}

run_rostest() {
  local hide=""
  if unshare -m true 2>/dev/null; then
    hide="unshare -m"
  elif unshare -rm true 2>/dev/null; then
    hide="unshare -rm"
  else
    echo "install-check: no mount namespace here: the source tree stays visible to the rostest"
  fi
  mkdir -p "$tmp/home"
  local run="rostest '$prefix/share/$pkg/test/tracker.test'"
  [ -n "$hide" ] && run="mount -t tmpfs -o size=1m,mode=0700 sgt-source-hidden '$root' && $run"
  env -i HOME="$tmp/home" PATH="$prefix/bin:/usr/bin:/bin" LANG=C.UTF-8 \
    ROS_PACKAGE_PATH="$prefix/share:/usr/share" CMAKE_PREFIX_PATH="$prefix:/usr" \
    LD_LIBRARY_PATH="$prefix/lib" PYTHONPATH="$prefix/lib/python3/dist-packages" \
    ROS_DISTRO="${ROS_DISTRO:-Debian}" ${SGT_SANITIZER_RUNTIME:+SGT_SANITIZER_RUNTIME=$SGT_SANITIZER_RUNTIME} \
    ${ASAN_OPTIONS:+ASAN_OPTIONS=$(relocated "$ASAN_OPTIONS")} \
    ${UBSAN_OPTIONS:+UBSAN_OPTIONS=$(relocated "$UBSAN_OPTIONS")} \
    ${LSAN_OPTIONS:+LSAN_OPTIONS=$(relocated "$LSAN_OPTIONS")} \
    ${TSAN_OPTIONS:+TSAN_OPTIONS=$(relocated "$TSAN_OPTIONS")} \
    $hide /bin/sh -c "$run" > "$tmp/rostest.log" 2>&1
  local status=$?
  tail -5 "$tmp/rostest.log"
  [ $status -eq 0 ] || fail "the tracker rostest from the install space failed (exit $status):"$'\n'"$(tail -12 "$tmp/rostest.log")"
  check_gtest_results "$tmp/home/.ros/test_results/$pkg"
  collect_sanitizer_logs
}

# rostest's exit status alone does not prove that the gtest program ran: its own result file must
# hold test cases, none failed.
check_gtest_results() {
  local verdict
  verdict="$(/usr/bin/python3 - "$1" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
cases, bad = 0, []
for path in glob.glob(sys.argv[1] + "/rosunit-*.xml"):
    for case in ET.parse(path).getroot().iter("testcase"):
        cases += 1
        error = case.find("failure") if case.find("failure") is not None else case.find("error")
        if error is not None:
            text = (error.text or error.get("message") or "").strip()
            bad.append("%s.%s: %s" % (case.get("classname"), case.get("name"), text[:1500]))
print("ok %d cases" % cases if cases and not bad else "%d of %d cases failed" % (len(bad), cases))
print("\n".join(bad))
PY
)"
  echo "install-check: gtest results: $verdict"
  [[ "$verdict" == ok* ]] || fail "the tracker rostest's gtest results ($1): $verdict"
}

install_package
check_no_source_paths
stage_rostest
run_rostest
finish
