"""The channel table, read from components/runtime/channels.h (the one table of channel names)."""
import re

from .paths import ROOT

_PATTERN = re.compile(r'inline constexpr char (k\w+)\[\] = "(DMPL_\w+)";')


def _load():
    text = (ROOT / "components/runtime/channels.h").read_text()
    table = {}
    for name, channel in _PATTERN.findall(text):
        # kHandStateTrue -> HAND_STATE_TRUE
        key = re.sub(r"(?<!^)(?=[A-Z])", "_", name[1:]).upper()
        table[key] = channel
    if not table:
        raise RuntimeError("no channels found in components/runtime/channels.h")
    return table


CHANNELS = _load()
globals().update(CHANNELS)
