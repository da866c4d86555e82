"""tools/dmpl replay LOG: plays a recorded log back onto LCM.

  --speed S        1 = as recorded (default), 2 = twice as fast, 0 = as fast as possible
  --channels RE    only channels matching this regex (default: all)
  --loop           start over at the end
  --answer CHANNEL lockstep: before publishing a message of tick k, wait until CHANNEL has
                   answered every tick before k (for re-running one process on recorded inputs)
  --compare        with --answer: compare the answers with the ones recorded in the log
  --single-bus     publish every channel on the one URL (for lcm-spy; see channels.h's buses)

Every dmpl message begins with utime and seq, so the tick of any message is read from its bytes.
Example, the controller alone on the sensed channels and tasks of a run:
  dmpl_controller --config RUN/config.yaml &
  tools/dmpl replay RUN/run.lcmlog --channels 'DMPL_(SENSORS|TASK)$' \\
      --answer DMPL_FINGER_TARGETS --compare
"""
import argparse
import re
import struct
import sys
import time

import lcm

from .bus import Buses
from .lcm_url import DEFAULT_LCM_URL, LcmUnavailable, refuse_if_in_use
from .process_set import SetError


def seq_of(data):
    """The lockstep seq of a dmpl message: fingerprint (8 bytes), utime (8), seq (8)."""
    return struct.unpack(">q", data[16:24])[0] if len(data) >= 24 else None


def read_events(path, pattern):
    """The log's events on channels matching `pattern`, one at a time (a full log of a long run
    does not fit in memory as Python objects)."""
    regex = re.compile(pattern)
    log = lcm.EventLog(str(path), "r")
    try:
        for e in log:
            if regex.match(e.channel):
                yield e.timestamp, e.channel, e.data
    finally:
        log.close()


def recorded(path, channel):
    log = lcm.EventLog(str(path), "r")
    out = {seq_of(e.data): e.data for e in log if e.channel == channel}
    log.close()
    return out


class Replayer:
    def __init__(self, url, separate=True):
        self.buses = Buses(url, separate)
        self.answers = {}

    def on_answer(self, channel, data):
        self.answers[seq_of(data)] = data

    def play(self, events, speed=1.0, answer=None, timeout=5.0):
        """Publishes the events. With `answer`, a message that starts a new tick (a seq above
        every one published so far) waits until the previous tick has been answered."""
        if answer:
            self.buses.subscribe(answer, self.on_answer)
        t0_log, t0 = None, time.monotonic()
        newest, played = None, 0
        for stamp, channel, data in events:
            t0_log = stamp if t0_log is None else t0_log
            played += 1
            s = seq_of(data)
            if answer and s is not None and newest is not None and s > newest:
                self.wait_for(newest, answer, timeout)
            elif not answer and speed > 0:
                wait = (stamp - t0_log) / 1e6 / speed - (time.monotonic() - t0)
                if wait > 0:
                    time.sleep(wait)
            if s is not None:
                newest = s if newest is None else max(newest, s)
            self.buses.publish(channel, data)
            self.buses.handle(0)
        if answer and newest is not None:
            self.wait_for(newest, answer, timeout)
        return played

    def wait_for(self, tick, answer, timeout):
        deadline = time.monotonic() + timeout
        while tick not in self.answers:
            if time.monotonic() > deadline:
                raise TimeoutError(f"no answer on {answer} for tick {tick}")
            self.buses.handle(0.01)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl replay", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log")
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--channels", default=".*")
    ap.add_argument("--loop", action="store_true")
    ap.add_argument("--answer")
    ap.add_argument("--compare", action="store_true")
    ap.add_argument("--lcm-url", default=None)
    ap.add_argument("--single-bus", action="store_true")
    args = ap.parse_args(argv)
    import os
    url = args.lcm_url or os.environ.get("LCM_DEFAULT_URL") or DEFAULT_LCM_URL
    try:
        re.compile(args.channels)
        next(read_events(args.log, args.channels))
    except re.error as e:
        print(f"dmpl replay: --channels is not a valid regex: {e}", file=sys.stderr)
        return 2
    except (OSError, IOError) as e:
        print(f"dmpl replay: cannot read '{args.log}': {e}", file=sys.stderr)
        return 2
    except StopIteration:
        print(f"dmpl replay: no events match '{args.channels}' in {args.log}", file=sys.stderr)
        return 2
    try:
        refuse_if_in_use(url)
    except SetError as e:
        print(f"dmpl replay: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl replay: {e}", file=sys.stderr)
        return 3
    player = Replayer(url, separate=not args.single_bus)
    print(f"dmpl replay: {args.log} onto {url}", file=sys.stderr)
    while True:
        try:
            played = player.play(read_events(args.log, args.channels), args.speed, args.answer)
        except TimeoutError as e:
            print(f"dmpl replay: {e}", file=sys.stderr)
            return 1
        print(f"dmpl replay: {played} messages played", file=sys.stderr)
        if not args.loop:
            break
    if args.answer and args.compare:
        expected = recorded(args.log, args.answer)
        same = sum(1 for s, d in player.answers.items() if expected.get(s) == d)
        differ = sorted(s for s, d in player.answers.items() if s in expected and expected[s] != d)
        missing = sorted(set(expected) - set(player.answers))
        print(f"dmpl replay: {same} answers identical to the log, {len(differ)} differ"
              f"{' (first at tick %d)' % differ[0] if differ else ''}, {len(missing)} missing")
        return 0 if not differ and not missing else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
