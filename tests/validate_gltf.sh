#!/bin/sh
# The gates' glTF check: the Khronos glTF-Validator (tools/validate_gltf.mjs) on FILE..., zero
# errors and zero warnings. Exits with the validator's code; when the validator is not installed
# (code 3) it notes that and exits 0, unless SYLVA_REQUIRE_GLTF_VALIDATOR=1 (make test sets it).
# WHAT names the files in the messages.
# usage: validate_gltf.sh WHAT FILE...
set -u
what=$1
shift
node tools/validate_gltf.mjs --max-warnings 0 "$@"
vrc=$?
if [ $vrc -eq 3 ] && [ "${SYLVA_REQUIRE_GLTF_VALIDATOR:-0}" != 1 ]; then
  echo "note: the glTF-Validator is not installed (tools/setup.sh); $what not validated"
  exit 0
fi
[ $vrc -ne 0 ] && echo "glTF-Validator: $what: errors or warnings (exit $vrc)" >&2
exit $vrc
