#!/usr/bin/env bash
# What a plugin author does with an installed stickslip, checked end to end:
#   1. `cmake --install` the build into a temporary prefix, then move the prefix (the tree must be relocatable) and
#      check that no installed binary refers to the build tree;
#   2. build plugins/example-spring out of tree against it with CMake (find_package(stickslip)), run its kit test;
#   3. build the same sources with pkg-config alone (stickslip.pc, stickslip-plugin-kit.pc), run that kit test;
#   4. run a scene with the out-of-tree plugin through the installed driver (STICKSLIP_PLUGIN_PATH; the installed
#      copy of example-spring is removed so the out-of-tree one is what loads).
# Usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/stickslip-install.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "install test: $*" >&2; exit 1; }

echo "== cmake --install into a temporary prefix, then moved"
cmake --install "$build" --prefix "$work/staged" >"$work/install.log" || { cat "$work/install.log"; fail "install failed"; }
mv "$work/staged" "$work/prefix"
prefix=$work/prefix
for f in "$prefix/bin/stickslip" "$prefix"/lib/*.so "$prefix"/lib/stickslip/plugins/*.so; do
  if readelf -d "$f" | grep -E 'R(UN)?PATH' | grep -q "$build"; then fail "$f keeps a path into the build tree"; fi
done
for f in include/stickslip/plugin.h include/stickslip/kit/plugin_kit.h lib/libstickslip_plugin_kit.so lib/libstickslip_gmsh.so \
         lib/cmake/stickslip/stickslipConfig.cmake lib/cmake/stickslip/stickslipConfigVersion.cmake \
         lib/pkgconfig/stickslip.pc lib/pkgconfig/stickslip-plugin-kit.pc lib/stickslip/plugins/libstickslip-penalty-nts.so \
         share/stickslip/scenes share/stickslip/meshes/block-2d.geo share/stickslip/tools/stickslip-compare share/doc/stickslip/writing-a-plugin.md; do
  [ -e "$prefix/$f" ] || fail "not installed: $f"
done
# the installed driver runs with no build tree on its paths and finds its plugins beside itself
env -u STICKSLIP_PLUGIN_PATH "$prefix/bin/stickslip" plugins >"$work/plugins.txt" || fail "installed driver: plugins failed"
grep -q "penalty-nts" "$work/plugins.txt" || { cat "$work/plugins.txt"; fail "installed driver lists no penalty-nts"; }
# the Python commands come along: `stickslip compare` runs from the install
"$prefix/bin/stickslip" compare --help >"$work/compare-help.txt" || fail "installed driver: compare --help failed"
grep -q -- "--closed-form" "$work/compare-help.txt" || fail "installed compare --help lacks --closed-form"
rm "$prefix/lib/stickslip/plugins/libstickslip-example-spring.so"

echo "== example-spring out of tree with CMake"
cmake -S "$src/plugins/example-spring" -B "$work/spring-cmake" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_COMPILE_WARNING_AS_ERROR=ON >"$work/cmake.log" \
  || { cat "$work/cmake.log"; fail "configure failed"; }
cmake --build "$work/spring-cmake" >"$work/build.log" 2>&1 || { cat "$work/build.log"; fail "CMake build failed"; }
ctest --test-dir "$work/spring-cmake" --output-on-failure || fail "kit test (CMake build) failed"
[ -f "$work/spring-cmake/libstickslip-example-spring.so" ] || fail "CMake build made no libstickslip-example-spring.so"

echo "== example-spring out of tree with pkg-config"
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
mkdir "$work/spring-pc"
cc $(pkg-config --cflags stickslip) $(pkg-config --variable=plugin_cflags stickslip) -Werror \
  -o "$work/spring-pc/libstickslip-example-spring.so" "$src/plugins/example-spring/example_spring.c" \
  $(pkg-config --variable=plugin_ldflags stickslip)
cc -std=c17 -Wall -Wextra -Werror $(pkg-config --cflags stickslip-plugin-kit) \
  -DEXAMPLE_SPRING_PATH="\"$work/spring-pc/libstickslip-example-spring.so\"" \
  -o "$work/spring-pc/test_example_spring" "$src/plugins/example-spring/test_example_spring.c" \
  $(pkg-config --libs stickslip-plugin-kit)
"$work/spring-pc/test_example_spring" || fail "kit test (pkg-config build) failed"
# --no-undefined is in force: a plugin calling into the core does not link
printf '#include "stickslip/plugin.h"\nint sk_error_set(int, const char *, ...);\nint f(void);\nint f(void) { return sk_error_set(1, "x"); }\n' >"$work/undefined.c"
if cc $(pkg-config --cflags stickslip) -fPIC -o "$work/undefined.so" "$work/undefined.c" \
     $(pkg-config --variable=plugin_ldflags stickslip) 2>/dev/null; then
  fail "a plugin with an undefined symbol linked (plugin_ldflags lacks --no-undefined)"
fi

echo "== a scene with the out-of-tree plugin through the installed driver"
cat >"$work/springs.yaml" <<YAML
description: a block pulled at its top, its bottom nodes on the out-of-tree example-spring
mesh:
  file: $prefix/share/stickslip/meshes/block-2d.geo
  parameters: {nx: 3, ny: 3}
bodies:
  - {name: block, group: body, material: {model: hooke, E: 100, nu: 0.3}}
boundary:
  - {name: pull, group: top, displacement: [0.02, 0.05], history: [[0, 0], [1, 1]]}
contact:
  - name: springs
    plugin: example-spring
    slave: bottom
    obstacle: {type: plane, point: [0, -1, 0], normal: [0, 1, 0]}
    parameters: {k: 5}
time: {scheme: quasi-static, dt: 0.5, end: 1}
output: {vtu: false}
YAML
if (cd "$work" && env -u STICKSLIP_PLUGIN_PATH "$prefix/bin/stickslip" run springs.yaml --out run-missing --quiet) \
     >"$work/missing.log" 2>&1; then
  fail "the removed plugin still loaded: the driver did not use its own install tree"
fi
grep -q "unknown plugin 'example-spring'" "$work/missing.log" || { cat "$work/missing.log"; fail "unexpected error"; }
cd "$work"
# the mesh cache off: the mesh generator's child loads the installed libstickslip_gmsh.so
STICKSLIP_MESH_CACHE=off STICKSLIP_PLUGIN_PATH=$work/spring-cmake "$prefix/bin/stickslip" run springs.yaml --out run-cmake --quiet
STICKSLIP_PLUGIN_PATH=$work/spring-pc "$prefix/bin/stickslip" run springs.yaml --out run-pc --quiet
for run in run-cmake run-pc; do
  grep -q '"status": "ok"' "$run/summary.json" || { cat "$run/summary.json"; fail "$run did not finish"; }
done
cmp -s <(cut -d, -f1-6 run-cmake/history.csv) <(cut -d, -f1-6 run-pc/history.csv) \
  || fail "the CMake and the pkg-config builds of example-spring ran differently"
echo "install test: passed"
