"""The LCM URL a run uses, and the check that no other run uses it."""
import os
import time

from . import channels
from .process_set import SetError

DEFAULT_LCM_URL = channels.DEFAULT_LCM_URL
RECEIVE_BUFFER_BYTES = 4 * 1024 * 1024

# Every launcher sends its status every 0.5 s (status_period_s): listening this long hears a run
# that is going on.
IN_USE_LISTEN_S = 0.6


class LcmUnavailable(Exception):
    """LCM cannot be opened on a URL: the tools exit 3, as the nodes do (README, "Exit codes")."""


def open_lcm(url):
    """An LCM instance on `url`; LcmUnavailable, with one line that says why, when there is none."""
    import lcm  # the PyPI package, in the project's venv
    try:
        return lcm.LCM(url)
    except RuntimeError:
        raise LcmUnavailable(f"cannot open LCM at '{url}' (a bad URL, or no multicast route: see "
                             "README)") from None


def resolve_lcm_url(given=None, configured=None):
    """The LCM URL: the one given (--lcm-url), else the configured one, else $LCM_DEFAULT_URL,
    else the dmpl default (as the nodes resolve it)."""
    return given or configured or os.environ.get("LCM_DEFAULT_URL") or DEFAULT_LCM_URL


def with_receive_buffer(url):
    """Adds a large socket receive buffer to a udpm URL. At 1 kHz lockstep every process reads
    every message on the group (~5 MB/s); the kernel's default 208 KB fills in 40 ms when a
    process is not scheduled, and a lost message stalls the lockstep or leaves a hole in the log.
    The kernel caps it at net.core.rmem_max (tools/dmpl raises that)."""
    if not url.startswith("udpm://") or "recv_buf_size" in url:
        return url
    return url + ("&" if "?" in url else "?") + f"recv_buf_size={RECEIVE_BUFFER_BYTES}"


def refuse_if_in_use(url, lc=None, listen_s=IN_USE_LISTEN_S):
    """Raises SetError when another run's launcher is heard on `url`: two runs on one URL would
    take each other's messages. Nodes started by hand are not a run (a user or a test may play
    one process of the set). memq:// is private to a process."""
    if not url.startswith("udpm://"):
        return
    if lc is None:
        lc = open_lcm(url)
    heard = []

    def on_status(channel, data):
        from dmpl import process_status_t
        try:
            status = process_status_t.decode(data)
            heard.append(f"the launcher of '{status.set_name}' (run directory {status.run_dir})")
        except ValueError:
            heard.append("a launcher")

    sub = lc.subscribe(channels.PROCESS_STATUS, on_status)
    end = time.monotonic() + listen_s
    try:
        while not heard and time.monotonic() < end:
            lc.handle_timeout(max(1, int((end - time.monotonic()) * 1000)))
    finally:
        lc.unsubscribe(sub)
    if heard:
        raise SetError(f"another run is using the LCM URL {url}: heard {heard[0]}. Two runs on "
                       "one URL take each other's messages: stop it, or give this run a URL of "
                       "its own (--lcm-url with another port, e.g. "
                       "udpm://239.255.76.67:7670?ttl=0)")
