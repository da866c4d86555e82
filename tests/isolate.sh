#!/bin/sh
# isolate.sh PORT CMD...: run a multi-process test so that it cannot hear any other test.
# Every test gets its own LCM port; as root it also gets a private network namespace with a
# multicast route on its own loopback (see tools/dmpl), so even equal ports cannot collide.
port=$1
shift
export LCM_DEFAULT_URL="udpm://239.255.76.67:${port}?ttl=0"
if [ "$(id -u)" = 0 ] && unshare -n true 2>/dev/null; then
  exec unshare -n sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && exec "$@"' sh "$@"
fi
exec "$@"
