"""The channel table and the default LCM URL, as C++ compiles them: the build generates the
module dmpl_channels (build/python/dmpl_channels.py, beside the LCM types) from
components/runtime/channels.h and config.h."""
import re

try:
    from dmpl_channels import BUSES, BUS_NAMES, CHANNELS, DEFAULT_LCM_URL
except ImportError as e:  # the build's python/ is not on the path, or not built yet
    raise ImportError("dmpl_channels not found: build dmpl (tools/dmpl build) and put its python/ "
                      "directory on PYTHONPATH") from e

globals().update(CHANNELS)

NUM_BUSES = max(BUSES.values()) + 1


def bus_of(channel):
    """The bus a channel travels on (channels.h); anything else is on the management bus."""
    return BUSES.get(channel, 0)


def bus_url(base_url, bus):
    """The URL of a bus: with udpm, the base port + 1000 * bus (as LcmBus::UrlFor)."""
    if bus == 0 or not base_url.startswith("udpm://"):
        return base_url
    m = re.match(r"(udpm://[^:/?]+):(\d+)(.*)", base_url)
    if not m:
        return base_url
    return f"{m.group(1)}:{int(m.group(2)) + 1000 * bus}{m.group(3)}"


def channel_url(base_url, channel, separate=True):
    return bus_url(base_url, bus_of(channel)) if separate else base_url
