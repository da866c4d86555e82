"""The channel table, read from components/runtime/channels.h (the one table of channel names)."""
import re

from .paths import ROOT

_PATTERN = re.compile(r'inline constexpr char (k\w+)\[\] = "(DMPL_\w+)";')


def _load():
    text = (ROOT / "components/runtime/channels.h").read_text()
    table = {}
    for name, channel in _PATTERN.findall(text):
        # kSensorsTrue -> SENSORS_TRUE
        key = re.sub(r"(?<!^)(?=[A-Z])", "_", name[1:]).upper()
        table[key] = channel
    if not table:
        raise RuntimeError("no channels found in components/runtime/channels.h")
    return table


CHANNELS = _load()
globals().update(CHANNELS)

_BUS = re.compile(r"\{k(\w+), (\d+)\},")


def _load_buses():
    text = (ROOT / "components/runtime/channels.h").read_text()
    table = {}
    for name, bus in _BUS.findall(text):
        key = re.sub(r"(?<!^)(?=[A-Z])", "_", name).upper()
        table[CHANNELS[key]] = int(bus)
    return table


BUSES = _load_buses()
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
