#!/usr/bin/env bash
# ctest Install.downstream_find_package: photoscene used as an installed library.
#
#   run_downstream_test.sh BUILD_DIR SOURCE_DIR CXX_COMPILER GENERATOR
#
# 1. cmake --install BUILD_DIR --prefix <tmp>/prefix (the build tree is already built), and checks
#    the tree: config files, headers, libraries, the command, the graph library, no path of the
#    source or build tree in the exported CMake files.
# 2. With the source and build trees hidden (a private mount namespace with empty folders mounted
#    over them, when `unshare -r -m` is allowed; else the checks below still hold), configures a
#    copy of tests/downstream with -DCMAKE_PREFIX_PATH=<tmp>/prefix, builds and installs it into
#    the prefix, runs its programs (they must find the installed graph library and viewer), and
#    runs the installed `photoscene graphs` command.
# 3. find_package(photoscene COMPONENTS <no such module>) and find_package(photoscene 99) must fail.
set -euo pipefail

if [ "${1:-}" = "--hidden" ]; then
  # inside the namespace: hide the trees, then run the rest
  shift
  for d in "$PS_HIDE_SOURCE" "$PS_HIDE_BUILD"; do
    if [ -d "$d" ]; then mount -t tmpfs -o size=1m ps-hidden "$d"; fi
  done
  if [ -e "$PS_HIDE_SOURCE/CMakeLists.txt" ]; then echo "FAILED: source tree still visible" >&2; exit 1; fi
  echo "[downstream] source and build trees hidden"
  exec "$@"
fi

BUILD=$(cd "$1" && pwd)
SRC=$(cd "$2" && pwd)
CXX_COMPILER=$3
GENERATOR=$4
t0=$EPOCHREALTIME
TMP=$(mktemp -d "${TMPDIR:-/tmp}/ps-downstream.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
PREFIX=$TMP/prefix
fail() { echo "FAILED: $*" >&2; exit 1; }
step() { echo "[downstream $(awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { printf "%5.1f s", b - a }')] $*"; }
# quiet unless it fails
run_logged() {
  local log=$1; shift
  if ! "$@" >"$log" 2>&1; then cat "$log" >&2; fail "$*"; fi
}

# ---- 1. install
step "cmake --install $BUILD --prefix $PREFIX"
run_logged "$TMP/install.log" cmake --install "$BUILD" --prefix "$PREFIX"
CMAKE_DIR=$(dirname "$(find "$PREFIX" -name photosceneConfig.cmake | head -1)")
[ -f "$CMAKE_DIR/photosceneConfig.cmake" ] || fail "no photosceneConfig.cmake under $PREFIX"
for f in photosceneConfigVersion.cmake photosceneTargets.cmake; do
  [ -f "$CMAKE_DIR/$f" ] || fail "no $f in $CMAKE_DIR"
done
for m in core graph render optim; do
  [ -f "$PREFIX/include/photoscene/$m.hpp" ] || fail "header photoscene/$m.hpp not installed"
  find "$PREFIX" -name "libps_$m.a" | grep -q . || fail "libps_$m.a not installed"
done
[ -x "$PREFIX/bin/photoscene" ] || fail "bin/photoscene not installed"
GRAPHS=$PREFIX/share/photoscene/graphs
n_src=$(find "$SRC/modules/graph/library" -maxdepth 1 -name '*.json' | wc -l)
n_inst=$(find "$GRAPHS" -maxdepth 1 -name '*.json' | wc -l)
[ "$n_src" -gt 0 ] && [ "$n_src" = "$n_inst" ] || fail "graph library: $n_inst of $n_src graphs installed"
if grep -rlF -e "$SRC" -e "$BUILD" "$CMAKE_DIR"; then fail "the exported CMake files name the source or build tree"; fi
VIEWER=$PREFIX/share/photoscene/viewer
VIEWER_ARG=()
if [ -f "$BUILD/share/photoscene/viewer/photoscene-viewer.js" ]; then
  [ -f "$VIEWER/photoscene-viewer.js" ] || fail "the report's viewer is built but not installed"
  VIEWER_ARG=("$VIEWER")
fi
step "installed: $(find "$PREFIX" -type f | wc -l) files, $(du -sh "$PREFIX" | cut -f1)"

# ---- 2. the downstream project, against the installed tree only
cp -r "$SRC/tests/downstream" "$TMP/project"
cat >"$TMP/downstream.sh" <<SCRIPT
set -euo pipefail
unset PHOTOSCENE_GRAPH_LIBRARY PHOTOSCENE_VIEWER_DIR
step() { echo "[downstream \$(awk -v a="$t0" -v b="\$EPOCHREALTIME" 'BEGIN { printf "%5.1f s", b - a }')] \$*"; }
cd "$TMP"
step "configure tests/downstream against $PREFIX"
cmake -S "$TMP/project" -B "$TMP/build" -G "$GENERATOR" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$CXX_COMPILER" -DCMAKE_PREFIX_PATH="$PREFIX" -DCMAKE_INSTALL_PREFIX="$PREFIX" \
  >"$TMP/configure.log" 2>&1 || { cat "$TMP/configure.log"; exit 1; }
step "build"
cmake --build "$TMP/build" >"$TMP/build.log" 2>&1 || { cat "$TMP/build.log"; exit 1; }
cmake --install "$TMP/build" >/dev/null
step "run"
"$PREFIX/bin/fit_part" "$GRAPHS"
if [ -x "$PREFIX/bin/all_modules" ]; then "$PREFIX/bin/all_modules" ${VIEWER_ARG[@]+"${VIEWER_ARG[@]}"}; fi
n=\$("$PREFIX/bin/photoscene" graphs --list | wc -l)
[ "\$n" = "$n_inst" ] || { echo "FAILED: photoscene graphs --list: \$n graphs, expected $n_inst" >&2; exit 1; }
"$PREFIX/bin/photoscene" graphs --render brick_red --size 16 -o "$TMP/out" >/dev/null
[ -s "$TMP/out/brick_red_albedo.png" ] || { echo "FAILED: photoscene graphs --render wrote nothing" >&2; exit 1; }
step "installed photoscene graphs: \$n graphs, brick_red rendered"
SCRIPT
case "$TMP/" in "$SRC"/* | "$BUILD"/*) hide=no ;; *) hide=yes ;; esac
mkdir -p "$TMP/probe"
if [ "$hide" = yes ] && unshare -r -m sh -c "mount -t tmpfs -o size=1m ps-probe '$TMP/probe'" 2>/dev/null; then
  PS_HIDE_SOURCE=$SRC PS_HIDE_BUILD=$BUILD unshare -r -m bash "$0" --hidden bash "$TMP/downstream.sh"
else
  step "cannot hide the source tree here (no user namespaces); the programs still check the folders they use"
  bash "$TMP/downstream.sh"
fi

# ---- 3. what must not configure
mkdir -p "$TMP/bad"
expect_failure() {  # name, find_package arguments, message the failure must contain
  cat >"$TMP/bad/CMakeLists.txt" <<CM
cmake_minimum_required(VERSION 3.22)
project(photoscene_bad LANGUAGES CXX)
find_package($2)
CM
  if cmake -S "$TMP/bad" -B "$TMP/bad/build-$1" -DCMAKE_PREFIX_PATH="$PREFIX" >"$TMP/bad-$1.log" 2>&1; then
    cat "$TMP/bad-$1.log" >&2
    fail "find_package($2) configured"
  fi
  grep -q "$3" "$TMP/bad-$1.log" || { cat "$TMP/bad-$1.log" >&2; fail "find_package($2): no '$3' in the error"; }
  step "find_package($2) fails as it should"
}
expect_failure component "photoscene REQUIRED COMPONENTS render no_such_module" "no module(s) no_such_module"
expect_failure version "photoscene 99 REQUIRED" "compatible with requested version \"99\""
step "ok"
