#!/bin/sh
# Prints RECIPE's `name:` (its outputs are OUT_DIR/<name>/<node>/), or fails with a one-line
# error when it has none. The gates' scripts check only their own recipe's outputs with it.
# usage: recipe_name.sh RECIPE
name=$(sed -n 's/^name:[[:space:]]*//p' "$1" | head -n 1)
[ -n "$name" ] || { echo "$1 has no 'name:' line" >&2; exit 1; }
printf '%s\n' "$name"
