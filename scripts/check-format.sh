#!/usr/bin/env bash
# Format check (part of `make test`): clang-format (Debian's package) in dry-run mode over the
# tracked C++ files (*.cpp, *.hpp) with the style in .clang-format (Google, 100 columns). Rewrites
# nothing; lists the files whose formatting differs and exits 1 when there are any.
#   scripts/check-format.sh [--xml=RESULT.xml]   (also writes the result as a JUnit test case)
# To fix a file: clang-format -i FILE.
source "$(dirname "$0")/check_common.sh" "$@"
cd "$root"
if ! command -v clang-format >/dev/null; then
  echo "clang-format not found (Debian package clang-format)" > "$report"
else
  # The tracked files; outside a git checkout, the C++ files of the source folders.
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    mapfile -t files < <(git ls-files -- '*.cpp' '*.hpp')
  else
    mapfile -t files < <(find benchmark include src test tools -name '*.cpp' -o -name '*.hpp' | sort)
  fi
  bad=()
  for f in "${files[@]}"; do
    [ -f "$f" ] || continue
    clang-format --dry-run --Werror --style=file "$f" >/dev/null 2>&1 || bad+=("$f")
  done
  if [ ${#bad[@]} -gt 0 ]; then
    {
      echo "${#bad[@]} of ${#files[@]} C++ files are not clang-formatted (clang-format -i FILE fixes one):"
      printf '  %s\n' "${bad[@]}"
    } > "$report"
  fi
  echo "clang-format: ${#files[@]} files checked, ${#bad[@]} not formatted"
fi
[ -s "$report" ] && cat "$report"
finish clang_format
