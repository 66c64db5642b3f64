#!/bin/sh
# ctest make_targets_call_existing_scripts: every script the Makefile and CI name (tools/..., .ci/...),
# and every script those name in turn, exists; the shell scripts among them are executable.
# usage: check_scripts.sh SOURCE_DIR
set -u
cd "$1" || exit 2
todo="Makefile .ci/run" seen="" bad=0
while [ -n "$todo" ]; do
  set -- $todo; f=$1; shift; todo="$*"
  case " $seen " in *" $f "*) continue ;; esac
  seen="$seen $f"
  # Names like tools/x.sh, .ci/x, tools/format-check (no variables, no globs).
  for ref in $(grep -v '^[[:space:]]*#' "$f" | grep -oE '(^|[^A-Za-z0-9_./-])(tools|\.ci)/[A-Za-z0-9_.-]+' | sed -E 's#^[^t.]*##'); do
    if [ ! -e "$ref" ]; then echo "$f names $ref, which does not exist"; bad=1; continue; fi
    case "$ref" in *.py|*.mjs|*.txt|*.json) ;; *) [ -x "$ref" ] || { echo "$f runs $ref, which is not executable"; bad=1; } ;; esac
    [ -f "$ref" ] && todo="$todo $ref"
  done
  # Scripts a script runs beside itself: "$(dirname "$0")/name".
  for name in $(grep -oE 'dirname "\$0"\)/[A-Za-z0-9_.-]+' "$f" | sed 's#.*)/##'); do
    ref=$(dirname "$f")/$name
    [ -d "$ref" ] && continue
    [ -e "$ref" ] || { echo "$f runs $ref beside itself, which does not exist"; bad=1; continue; }
    todo="$todo $ref"
  done
done
[ $bad -eq 0 ] && echo "scripts named by the Makefile and CI:$seen"
exit $bad
