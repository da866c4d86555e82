#!/bin/sh
# The README draws the statecharts as the supervisor exports them: keep it true.
build=$1
root=$2
DMPL_ROOT="$root" "$build/bin/dmpl_supervisor" --mermaid | grep -- '-->' | sed 's/^ *//' > /tmp/dmpl_charts.$$
missing=0
while IFS= read -r line; do
  grep -qF -- "$line" "$root/README.md" || { echo "README lacks: $line"; missing=1; }
done < /tmp/dmpl_charts.$$
rm -f /tmp/dmpl_charts.$$
exit $missing
