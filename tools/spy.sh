#!/usr/bin/env bash
# lcm-spy with dmpl's types, on Java 17 (Debian's /usr/bin/lcm-spy passes -Xincgc and dies).
# usage: spy.sh BUILD_DIR [lcm-spy args...]; without a display it runs under xvfb-run.
set -euo pipefail
build="$1"; shift
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
