#!/usr/bin/env bash
# Style checks that need no test run: every C++ file clang-formatted, and no function in src/
# longer than 120 lines (clang-tidy's readability-function-size, counted from the opening to
# the closing brace, blank and comment lines included; headers under src/ too).
#   bash scripts/lint.sh [BUILD_DIR]    (default build/, for its compile_commands.json)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
missing=()
command -v clang-format >/dev/null || missing+=(clang-format)
command -v clang-tidy >/dev/null || missing+=(clang-tidy)
if ((${#missing[@]})); then
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
[[ -f "$build/compile_commands.json" ]] || bash scripts/build.sh "$build"

status=0
files=$(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp')
if ! clang-format --dry-run --Werror $files 2>/tmp/tpmsfill-format.txt; then
  grep -o '^[^:]*:' /tmp/tpmsfill-format.txt | sort -u | sed 's/:$/: not clang-formatted/'
  status=1
fi

config="{Checks: '-*,readability-function-size', CheckOptions: [{key: readability-function-size.LineThreshold, value: 120}]}"
sources=$(git ls-files --cached --others --exclude-standard 'src/*.cpp')
long=$(printf '%s\n' $sources | xargs -P "$(nproc)" -n 4 clang-tidy -p "$build" --quiet \
         --config="$config" -header-filter="$PWD/src/.*" 2>/dev/null |
       grep -E "warning: function .* exceeds" | sort -u || true)
if [[ -n "$long" ]]; then
  echo "$long"
  status=1
fi
((status == 0)) && echo "lint: formatted, no function in src/ over 120 lines"
exit $status
