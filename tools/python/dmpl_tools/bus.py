"""LCM on dmpl's buses from Python: one instance per bus a channel travels on (channels.h)."""
import select

from .channels import channel_url
from .lcm_url import open_lcm


class Buses:
    """Publishes and subscribes each channel on its own bus; spins all of them."""

    def __init__(self, base_url, separate=True):
        self.base_url, self.separate = base_url, separate
        self.instances = {}

    def lcm_for(self, channel):
        url = channel_url(self.base_url, channel, self.separate)
        if url not in self.instances:
            self.instances[url] = open_lcm(url)
        return self.instances[url]

    def subscribe(self, channel, handler):
        return self.lcm_for(channel).subscribe(channel, handler)

    def publish(self, channel, data):
        self.lcm_for(channel).publish(channel, data)

    def handle(self, timeout_s):
        """Waits up to timeout_s for traffic on any bus and handles all that is there."""
        instances = list(self.instances.values())
        if not instances:
            return 0
        ready, _, _ = select.select([l.fileno() for l in instances], [], [], timeout_s)
        handled = 0
        for l in instances:
            if l.fileno() in ready:
                while l.handle_timeout(0) > 0:
                    handled += 1
        return handled
