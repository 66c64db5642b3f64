#!/bin/sh
# The `sylva` binary never loads OpenImageIO, EGL/GL or its graphics module for commands that do
# not render (docs/architecture.md, "Heavy libraries load lazily"): --help, stages, graph and
# explain of a recipe with a verify node, and a build (and its no-op) of light nodes. As a
# control, `render --help` must load the module. Uses glibc's LD_DEBUG=libs.
# Usage: startup_libs.sh SYLVA_BINARY
set -u
sylva=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat >"$dir/r.yaml" <<YAML
version: 1
name: startup
nodes:
  tree:
    stage: generate
    with: { preset: $(pwd)/configs/species/oak.yaml, age: young, seed: 3 }
  mesh:
    stage: mesh
    needs: [tree]
    with: { subdivision: 0 }
  check:
    stage: verify
    needs: [mesh]
    with: { cameras: $(pwd)/configs/cameras/verify.yaml, references: $(pwd)/tests/verify/references }
YAML
heavy='OpenImageIO|libEGL|libGLX|libGL\.so|libsylva_gfx'
fail=0
check() {  # check NAME should_load COMMAND...
  name=$1 want=$2
  shift 2
  if ! LD_DEBUG=libs "$@" >"$dir/stdout" 2>"$dir/libs"; then
    echo "FAIL: $name: exit code $? ($*)"
    grep -v "^ *[0-9]*:" "$dir/libs" | tail -5
    fail=1
    return
  fi
  if grep -Eq "calling init: .*($heavy)" "$dir/libs"; then got=yes; else got=no; fi
  if [ "$got" != "$want" ]; then
    echo "FAIL: $name: heavy libraries loaded: $got (expected $want)"
    grep -E "calling init: .*($heavy)" "$dir/libs" | head -3
    fail=1
  else
    echo "ok: $name (heavy libraries loaded: $got)"
  fi
}
check "--help" no "$sylva" --help
check "stages" no "$sylva" stages
check "graph" no "$sylva" graph "$dir/r.yaml"
check "explain" no "$sylva" --out "$dir/out" explain "$dir/r.yaml" check
check "build of light nodes" no "$sylva" --out "$dir/out" build "$dir/r.yaml" --target mesh
check "no-op build" no "$sylva" --out "$dir/out" build "$dir/r.yaml" --target mesh
check "render --help (control)" yes "$sylva" render --help
exit $fail
