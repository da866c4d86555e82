#!/usr/bin/env bash
# lcm-spy with dmpl's types, on Java 17 (Debian's /usr/bin/lcm-spy passes -Xincgc and dies).
# usage: spy.sh BUILD_DIR [--bus NAME] [lcm-spy args...]; without a display it runs under xvfb-run.
# dmpl puts each group of channels on its own port (components/runtime/channels.h): --bus picks
# which one to watch (management by default; the names are the build's, dmpl_channels.py), or
# replay a log with `tools/dmpl replay LOG --single-bus` to see every channel on one URL.
set -euo pipefail
build="$1"; shift
table="$build/python/dmpl_channels.py"
[ -f "$table" ] || { echo "dmpl spy: $table is missing (run tools/dmpl build)" >&2; exit 2; }
# The default URL, then the bus names, as C++ compiles them.
mapfile -t generated < <(python3 -c 'import runpy, sys
t = runpy.run_path(sys.argv[1])
print(t["DEFAULT_LCM_URL"]); print("\n".join(t["BUS_NAMES"]))' "$table")
default_url="${generated[0]}"
buses=("${generated[@]:1}")
bus=0
if [ "${1:-}" = "--bus" ]; then
  for i in "${!buses[@]}"; do [ "${buses[$i]}" = "${2:-}" ] && bus=$i; done
  [ "${buses[$bus]}" = "${2:-}" ] || { echo "dmpl spy: unknown bus '${2:-}' (${buses[*]})" >&2; exit 2; }
  shift 2
fi
base="${LCM_DEFAULT_URL:-$default_url}"
if [ "$bus" -gt 0 ]; then
  # The bus's URL by the rule the nodes use (components/runtime/lcm_url.h, through Python).
  LCM_DEFAULT_URL=$(PYTHONPATH="$build/python:$(dirname "$0")/python" python3 -c '
import sys
from dmpl_tools.channels import bus_url
try:
    print(bus_url(sys.argv[1], int(sys.argv[2])))
except ValueError as e:
    sys.exit(f"dmpl spy: {e}")' "$base" "$bus") || exit 2
  export LCM_DEFAULT_URL
fi
echo "dmpl spy: the ${buses[$bus]} bus, ${LCM_DEFAULT_URL:-$base}" >&2
jar="$build/java/dmpl_types.jar"
[ -f "$jar" ] || { echo "dmpl spy: $jar is missing (run tools/dmpl build)" >&2; exit 2; }
cp="/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$jar"
# lcm-spy finds types by scanning CLASSPATH.
export CLASSPATH="$cp"
cmd=(java -XX:+IgnoreUnrecognizedVMOptions -cp "$cp" lcm.spy.Spy)
[ -n "${LCM_DEFAULT_URL:-}" ] && cmd+=(--lcm-url="$LCM_DEFAULT_URL")
if [ -z "${DISPLAY:-}" ]; then
  echo "dmpl spy: no DISPLAY; running under a virtual display (xvfb-run)" >&2
  exec xvfb-run -a "${cmd[@]}" "$@"
fi
exec "${cmd[@]}" "$@"
