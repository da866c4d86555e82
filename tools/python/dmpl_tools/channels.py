"""The channel table and the default LCM URL, as C++ compiles them: the build generates the
module dmpl_channels (build/python/dmpl_channels.py, beside the LCM types) from
components/runtime/channels.h and config.h."""
import ctypes
import functools
from pathlib import Path

try:
    import dmpl_channels
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
    """The URL of a bus, by the rule C++ uses (components/runtime/lcm_url.h): with udpm the base
    port (LCM's 7667 when the URL gives none) + 1000 * bus, options kept. Raises ValueError for a
    udpm URL whose port is not one."""
    out = ctypes.create_string_buffer(2 * len(base_url) + 256)  # the URL, or why not
    code = _lcm_url().dmpl_bus_url(base_url.encode(), bus, out, len(out))
    if code != 0:
        raise ValueError(out.value.decode())
    return out.value.decode()


@functools.lru_cache(maxsize=1)
def _lcm_url():
    lib = Path(dmpl_channels.__file__).with_name("libdmpl_lcm_url.so")
    try:
        c = ctypes.CDLL(str(lib))
    except OSError as e:
        raise ImportError(f"{lib}: {e} (run tools/dmpl build)") from None
    c.dmpl_bus_url.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_int]
    c.dmpl_bus_url.restype = ctypes.c_int
    return c


def channel_url(base_url, channel, separate=True):
    return bus_url(base_url, bus_of(channel)) if separate else base_url
