#!/usr/bin/env bash
# dynpm.sh — the project's two commands, on a fresh Debian 12 machine:
#   ./dynpm.sh demo   install what is missing, build (Release), run dynpm on the shipped sample
#   ./dynpm.sh test   install what is missing, build with -Werror, run every test (CTest)
# Also: ./dynpm.sh sanitize (every test under AddressSanitizer + UndefinedBehaviorSanitizer),
#       ./dynpm.sh build (just build), ./dynpm.sh deps (just install),
#       ./dynpm.sh bench-deps (the peers of bench/peers, docs/peers.md; benchmarks only).
set -euo pipefail
cd "$(dirname "$0")"

# Debian packages: the toolchain and test libraries; the third-party tools the tests compare
# against (meshio writes and reads files nobody here wrote, Exodus through python3-netcdf4;
# python3-vtk9 is VTK's own reader; libcgal-dev's Hausdorff distance checks dynpm's; the viewer's
# tests run in Node.js and Debian's headless Chromium; clang-format checks the C++ formatting;
# strace counts the files a command opens;
# slurm-wlm and munge run the one-node cluster that 'dynpm batch --slurm' is tested on).
BUILD_PACKAGES=(g++ cmake ninja-build xz-utils pkg-config libzstd-dev libnetcdf-dev zlib1g-dev)
TEST_PACKAGES=(libgtest-dev libgmock-dev clang-format strace python3-meshio python3-netcdf4 python3-vtk9 libcgal-dev nodejs npm chromium calculix-ccx slurm-wlm munge)
# The test and sanitizer builds keep line tables only (-g1): file and line in every assertion
# and sanitizer trace, without the cost of full debug info (the test build from scratch on two
# cores: 10.7 -> 6.4 min; CI compiles everything twice on a fresh machine).
TEST_DEBUG_INFO=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
# The peers bench/peers compares dynpm with (never needed to build or test dynpm).
BENCH_PACKAGES=(libmeshoptimizer-dev libopenmesh-dev libcgal-dev gltfpack draco)

# Node.js from another source (NodeSource's nodejs bundles npm and conflicts with Debian's npm)
# counts as installed when its command is on PATH.
declare -A PACKAGE_COMMAND=([nodejs]=node [npm]=npm)

install_packages() {
  local missing=()
  for p in "$@"; do
    [ -n "${PACKAGE_COMMAND[$p]:-}" ] && command -v "${PACKAGE_COMMAND[$p]}" >/dev/null && continue
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "dynpm.sh: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# The shipped sample: a CalculiX hat-rail animation as an OBJ sequence (data/hat-rail/README.md).
SAMPLE_ARCHIVE=data/hat-rail/frames.tar.xz
SAMPLE_DIR=build/sample/hat-rail

unpack_sample() {
  if [ ! -f "$SAMPLE_DIR/.unpacked" ] || [ "$SAMPLE_ARCHIVE" -nt "$SAMPLE_DIR/.unpacked" ]; then
    rm -rf "$SAMPLE_DIR" && mkdir -p "$SAMPLE_DIR"
    tar -xJf "$SAMPLE_ARCHIVE" -C "$SAMPLE_DIR"
    touch "$SAMPLE_DIR/.unpacked"
  fi
}

# The viewer's npm packages (three.js, fzstd, playwright-core), exactly as package-lock.json
# says; the build compiles three.js and fzstd into dynpm (viewer/embed/assets.cmake).
viewer_modules() {
  command -v npm >/dev/null || return 0
  if [ ! -f viewer/node_modules/.package-lock.json ] ||
    [ viewer/package-lock.json -nt viewer/node_modules/.package-lock.json ]; then
    (cd viewer && npm ci --no-audit --no-fund --loglevel=error)
  fi
}

build_release() {
  viewer_modules
  cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DDYNPM_BUILD_TESTS=OFF \
    -DDYNPM_BUILD_BENCH=OFF >/dev/null
  cmake --build build/release
}

case "${1:-}" in
  deps)
    install_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
    ;;
  build)
    install_packages "${BUILD_PACKAGES[@]}"
    build_release
    ;;
  bench-deps)
    install_packages "${BENCH_PACKAGES[@]}"
    ;;
  demo)
    install_packages "${BUILD_PACKAGES[@]}"
    build_release
    unpack_sample
    dynpm=build/release/cli/dynpm
    echo
    zcat data/hat-rail/rail.frd.gz > build/sample/rail.frd
    mkdir -p build/demo
    echo "== 1. The shipped CalculiX result, read directly from its .frd"
    echo "\$ dynpm info build/sample/rail.frd"
    "$dynpm" info build/sample/rail.frd
    echo
    echo "== 2. Pre-processed once into a dynamic progressive mesh (every step rates the collapses)"
    echo "\$ dynpm build build/sample/rail.frd -o build/demo/rail.dpm"
    "$dynpm" build build/sample/rail.frd -o build/demo/rail.dpm
    echo
    echo "== 3. Any resolution at any time step: 10% of the vertices at the last step"
    echo "\$ dynpm extract build/demo/rail.dpm --ratio 0.1 --step 30 -o build/demo/rail10_step30.vtu"
    "$dynpm" extract build/demo/rail.dpm --ratio 0.1 --step 30 -o build/demo/rail10_step30.vtu
    echo
    echo "Browse it with time and resolution sliders: $dynpm view build/demo/rail.dpm"
    ;;
  test)
    install_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
    viewer_modules
    # Optimised, warnings as errors, assertions on.
    cmake -S . -B build/test -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${TEST_DEBUG_INFO[@]}" \
      -DDYNPM_WERROR=ON -DDYNPM_ASSERTS=ON -DDYNPM_BUILD_TESTS=ON >/dev/null
    cmake --build build/test
    DYNPM_REQUIRE_THIRD_PARTY=1 ctest --test-dir build/test --output-on-failure -j "$(nproc)"
    ;;
  sanitize)
    install_packages "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
    viewer_modules
    cmake -S . -B build/sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${TEST_DEBUG_INFO[@]}" \
      -DDYNPM_WERROR=ON -DDYNPM_ASSERTS=ON -DDYNPM_BUILD_TESTS=ON \
      -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" \
      -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
    cmake --build build/sanitize
    # The rules (tests/rules: modules, sizes, format, copies) read the sources; `test` ran them.
    # The *_browser tests drive the page's JavaScript in Chromium, which no sanitizer sees, and a
    # third of this lane's time; the C++ they reach (view, serve, build) stays in viewer_server,
    # viewer_serve, viewer_security, viewer_cli and the conformance tests. The comparisons with
    # CGAL's distance (EvalCgal: CGAL's templates, instrumented too, took 154 of the lane's 590
    # test seconds, 8x the test lane's) are the test lane's; dynpm's Hausdorff code stays under
    # the sanitizers in the other Eval* and Hausdorff* tests.
    DYNPM_REQUIRE_THIRD_PARTY=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build/sanitize --output-on-failure -j "$(nproc)" -E '^rules_|_browser$|^EvalCgal\.'
    ;;
  *)
    echo "usage: ./dynpm.sh demo | test | sanitize | build | deps | bench-deps" >&2
    exit 2
    ;;
esac
