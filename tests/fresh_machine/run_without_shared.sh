#!/bin/sh
# ctest default_recipe_without_shared_data: copies the repository's files (not out/, not .git)
# to WORK/repo, where WORK/shared does not exist, and runs what `make run` runs there except
# lodcheck (ctest lodcheck_default_recipe proves the same recipe's levels): `sylva build` and
# `sylva verify` of configs/default.yaml with SYLVA_DATA_DIR unset and a fresh cache. Fails if
# the recipe reads anything outside the repository.
# usage: run_without_shared.sh SYLVA SOURCE_DIR WORK_DIR
set -u
sylva=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work/repo" || exit 1
(cd "$src" && tar --exclude=./out --exclude=./.git -cf - .) | (cd "$work/repo" && tar -xf -) || exit 1
[ ! -e "$work/shared" ] || { echo "$work/shared exists" >&2; exit 1; }
unset SYLVA_DATA_DIR
cd "$work/repo" || exit 1
"$sylva" --out "$work/out" build configs/default.yaml || { echo "make run's build failed without ../shared" >&2; exit 1; }
"$sylva" --out "$work/out" verify configs/default.yaml || { echo "make run's verify failed without ../shared" >&2; exit 1; }
rm -rf "$work"
