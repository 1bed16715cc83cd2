#!/usr/bin/env bash
# catkin_lint check (part of `make test`): Debian's catkin-lint over the package, errors and
# warnings (-W1) fail. On Debian there is no rosdep database and no network index: --offline, and
# ROS_DISTRO from rosversion ("Debian") when unset; the ROS packages it checks against are found in
# /usr/share. Exits 1 on any problem.
#   scripts/check-catkin-lint.sh [--xml=RESULT.xml]   (also writes the result as a JUnit test case)
source "$(dirname "$0")/check_common.sh" "$@"
export ROS_DISTRO="${ROS_DISTRO:-$(rosversion -d 2>/dev/null || echo Debian)}"
out=""
if ! command -v catkin_lint >/dev/null; then
  echo "catkin_lint not found (Debian package catkin-lint)" | tee "$report"
else
  out="$(catkin_lint --offline --color never -W1 --strict "$root" 2>&1)"
  status=$?
  # Without python3-rosdep2 it says so and ignores system dependencies: not a finding.
  out="$(grep -v -e 'cannot load rosdep database' -e 'unknown dependencies will be ignored' <<< "$out")"
  echo "$out"
  [ $status -ne 0 ] && echo "catkin_lint found problems in $root (exit $status):"$'\n'"$out" > "$report"
fi
finish catkin_lint
