#!/usr/bin/env bash
# Style checks that need no test run: every C++ file clang-formatted, and no function in src/
# longer than 120 lines (clang-tidy's readability-function-size, counted from the opening to
# the closing brace, blank and comment lines included; headers under src/ too).
#   bash scripts/lint.sh [BUILD_DIR]    (default build/, for its compile_commands.json)
# Exit 0: clean; 1: a file to format or a function too long (each named); 2: the check itself
# could not run (a tool missing, a file clang-tidy could not parse).
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
missing=()
command -v clang-format >/dev/null || missing+=(clang-format)
command -v clang-tidy >/dev/null || missing+=(clang-tidy)
if ((${#missing[@]})); then
  echo "lint: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
if [[ ! -f "$build/compile_commands.json" ]]; then
  echo "lint: no $build/compile_commands.json; configuring and building $build first"
  bash scripts/build.sh "$build"
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp')
if ! clang-format --dry-run --Werror "${files[@]}" 2>"$tmp/format.txt"; then
  grep -o '^[^:]*:' "$tmp/format.txt" | sort -u | sed 's/:$/: not clang-formatted/'
  status=1
fi

config="{Checks: '-*,readability-function-size', CheckOptions: [{key: readability-function-size.LineThreshold, value: 120}]}"
mapfile -t sources < <(git ls-files --cached --others --exclude-standard 'src/*.cpp')
if ! printf '%s\n' "${sources[@]}" |
    xargs -P "$(nproc)" -n 4 clang-tidy -p "$build" --quiet --config="$config" \
      -header-filter="$PWD/src/.*" >"$tmp/tidy.txt" 2>"$tmp/tidy-errors.txt"; then
  echo "lint: clang-tidy could not analyse every source (is $build configured for this tree?):"
  grep -h -m 5 "error:" "$tmp/tidy.txt" || tail -5 "$tmp/tidy-errors.txt"
  exit 2
fi
# "FILE:LINE: function 'NAME' is N lines (at most 120)", from each warning and its note.
awk '/warning: function .* exceeds/ { split($0, w, ": warning: "); match($0, /function [^ ]+/);
                                      where = w[1]; name = substr($0, RSTART, RLENGTH) }
     /note: [0-9]+ lines including/ && where { match($0, /[0-9]+ lines/);
       print where ": " name " is " substr($0, RSTART, RLENGTH) " (at most 120)"; where = "" }' \
  "$tmp/tidy.txt" | sort -u >"$tmp/long.txt"
if [[ -s "$tmp/long.txt" ]]; then
  cat "$tmp/long.txt"
  status=1
fi
((status == 0)) && echo "lint: ${#files[@]} files formatted, no function in src/ over 120 lines"
exit $status
