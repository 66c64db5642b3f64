#!/bin/sh
# Every stage the binary registers (`sylva stages`) has its reference page docs/stages/<name>.md
# and a row in docs/stages.md (CONTRIBUTING.md, "Adding a stage"). Usage: stages_documented.sh SYLVA
set -eu
sylva=$1
names=$("$sylva" stages | sed -n 's/^\([a-z_][a-z_]*\) (v[0-9][0-9]*):.*/\1/p')
[ -n "$names" ] || { echo "stages_documented: 'sylva stages' listed no stage"; exit 1; }
status=0
for n in $names; do
  [ -f "docs/stages/$n.md" ] || { echo "stage '$n' has no page docs/stages/$n.md"; status=1; }
  grep -q "^| \`$n\` |" docs/stages.md || { echo "stage '$n' has no row in docs/stages.md"; status=1; }
done
[ $status -eq 0 ] && echo "stages_documented: $(echo $names | wc -w) stages, each with its page and row"
exit $status
