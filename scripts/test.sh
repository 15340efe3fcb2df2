#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test with ctest.
#   bash scripts/test.sh              Release build in build/
#   bash scripts/test.sh --sanitize   AddressSanitizer + UndefinedBehaviorSanitizer, in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."

# The web page's test runs in Debian's chromium: installed where it can be; where it cannot,
# ctest lists that test as skipped, saying why.
browser() {
  command -v chromium > /dev/null && return
  TPMSFILL_SETUP_EXTRA=chromium bash scripts/setup.sh ||
    echo "test: chromium could not be installed: the web page's browser test will be skipped"
}

if [[ "${1:-}" == "--sanitize" ]]; then
  TPMSFILL_SETUP_EXTRA=clang bash scripts/setup.sh
  browser
  bash scripts/build.sh build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTPMSFILL_SANITIZE=address,undefined
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
  export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp"  # lib3mf's own leak
  ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)"
  exit
fi

bash scripts/setup.sh
browser
# MPI is optional: where Open MPI is installed, the tool is built with it and the mpirun test
# runs; elsewhere that test is skipped with a message.
mpi=()
command -v mpicxx > /dev/null && command -v mpirun > /dev/null && mpi=(-DTPMSFILL_MPI=ON)
# The Python module against Debian's interpreter, whose numpy and pytest setup.sh installs (a
# pyenv or venv python3 earlier on PATH may have neither).
python=(-DTPMSFILL_PYTHON=ON)
[[ -x /usr/bin/python3 ]] && python+=(-DPython3_EXECUTABLE=/usr/bin/python3)
bash scripts/build.sh build "${mpi[@]}" "${python[@]}"
# `import tpmsfill` from anywhere: a .pth in the interpreter's user site naming build/python
# (the user's own folder, nothing system-wide; removed by deleting the file it prints).
py=/usr/bin/python3
[[ -x $py ]] || py=python3
if site=$("$py" -m site --user-site 2> /dev/null) && mkdir -p "$site" 2> /dev/null &&
  echo "$PWD/build/python" > "$site/tpmsfill-build.pth"; then
  echo "test: $py imports tpmsfill from $PWD/build/python ($site/tpmsfill-build.pth)"
fi
ctest --test-dir build --output-on-failure --parallel "$(nproc)"
