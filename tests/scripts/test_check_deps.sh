#!/usr/bin/env bash
# scripts/check-deps against the build folder it runs in: it passes with the real package list, fails naming
# libopenvdb-dev when that package is taken out of a copy of the list (mapping/ includes OpenVDB's headers and
# nothing else in the list depends on libopenvdb-dev), and gives a clear error and exit 1 for a missing build
# folder and for a system without dpkg. Exit 77 (skipped) where there is no dpkg to test with.
# Usage: test_check_deps.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
source_dir=$1 build_dir=$2
check="$source_dir/scripts/check-deps"
command -v dpkg-query >/dev/null || { echo "SKIP: no dpkg on this system"; exit 77; }
[[ -f "$build_dir/build.ninja" ]] || { echo "SKIP: $build_dir is not a Ninja build (check-deps reads its logs)"; exit 77; }

failures=0
expect() {  # expect NAME WANTED_EXIT PATTERN -- command...
  local name=$1 wanted=$2 pattern=$3
  shift 4
  local output code
  output=$("$@" 2>&1)
  code=$?
  if [[ $code != "$wanted" ]] || ! grep -qE -- "$pattern" <<<"$output"; then
    echo "FAIL $name: exit $code (wanted $wanted), output without /$pattern/:"
    echo "$output" | head -20
    failures=$((failures + 1))
  else
    echo "ok   $name"
  fi
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed 's/\<libopenvdb-dev\>//' "$source_dir/scripts/debian-packages.txt" >"$work/without-openvdb.txt"
grep -q libopenvdb-dev "$work/without-openvdb.txt" && { echo "FAIL: could not take libopenvdb-dev out"; exit 1; }

expect "the real list passes" 0 "come from [0-9]+ packages" -- "$check" "$build_dir"
expect "a list without libopenvdb-dev fails, naming it and a file" 1 \
  "libopenvdb-dev is used but neither in .*: /usr/include/openvdb/.*\.h" -- \
  "$check" "$build_dir" --packages "$work/without-openvdb.txt"
expect "a missing build folder is a clear error" 1 "$work/no-build: no such build folder" -- \
  "$check" "$work/no-build"
expect "a folder that is not a build is a clear error" 1 "not a configured Ninja build folder" -- \
  "$check" "$work"
expect "no dpkg is a clear error" 1 "dpkg not found" -- env PATH="$work" /bin/bash "$check" "$build_dir"
expect "an unknown option is a usage error" 2 "unknown option --frobnicate" -- "$check" --frobnicate

echo "$((6 - failures)) passed, $failures failed"
((failures == 0))
