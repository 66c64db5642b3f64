#!/bin/sh
# The `sylva` binary never loads OpenImageIO, EGL/GL or its graphics module for commands that do
# not render, nor OpenMesh, CGAL's GMP, Draco, tinygltf or its geometry module unless a mesh or
# lod node runs (docs/architecture.md, "Heavy libraries load lazily"): --help, stages, graph and
# explain of a recipe with mesh and verify nodes, and a no-op build load neither; building the
# mesh node loads the geometry module only. As a control, `render --help` must load the graphics
# module (which links Draco and tinygltf itself). Uses glibc's LD_DEBUG=libs.
# Usage: startup_libs.sh SYLVA_BINARY
set -u
sylva=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat >"$dir/r.yaml" <<YAML
version: 1
name: startup
root: $(pwd)
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
gfx='OpenImageIO|libEGL|libGLX|libGL\.so|libsylva_gfx'
geometry='OpenMesh|libgmp|libdraco|libtinygltf|libsylva_geometry'
fail=0
loads() {  # loads PATTERN: yes if the last command's LD_DEBUG log initialised a library matching it
  if grep -Eq "calling init: .*($1)" "$dir/libs"; then echo yes; else echo no; fi
}
check() {  # check NAME GFX(yes|no) GEOMETRY(yes|no) COMMAND...
  name=$1 want=$2 want_geometry=$3
  shift 3
  if ! LD_DEBUG=libs "$@" >"$dir/stdout" 2>"$dir/libs"; then
    echo "FAIL: $name: exit code $? ($*)"
    grep -v "^ *[0-9]*:" "$dir/libs" | tail -5
    fail=1
    return
  fi
  got=$(loads "$gfx") got_geometry=$(loads "$geometry")
  if [ "$got" != "$want" ] || [ "$got_geometry" != "$want_geometry" ]; then
    echo "FAIL: $name: graphics libraries loaded: $got (expected $want), geometry: $got_geometry (expected $want_geometry)"
    grep -E "calling init: .*($gfx|$geometry)" "$dir/libs" | head -3
    fail=1
  else
    echo "ok: $name (graphics libraries loaded: $got, geometry: $got_geometry)"
  fi
}
check "--help" no no "$sylva" --help
check "stages" no no "$sylva" stages
check "graph" no no "$sylva" graph "$dir/r.yaml"
check "explain" no no "$sylva" --out "$dir/out" explain "$dir/r.yaml" check
check "build of a mesh node" no yes "$sylva" --out "$dir/out" build "$dir/r.yaml" --target mesh
check "no-op build" no no "$sylva" --out "$dir/out" build "$dir/r.yaml" --target mesh
check "render --help (control)" yes yes "$sylva" render --help
exit $fail
