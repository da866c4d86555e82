"""Headless Chromium driven over the DevTools protocol, for tests of pages: open a URL, evaluate
JavaScript in it. Tornado (a dependency of Meshcat, in the project's venv) is the WebSocket
client."""
import json
import re
import shutil
import subprocess
import tempfile
import time
import urllib.request

from tornado.ioloop import IOLoop
from tornado.websocket import websocket_connect

BROWSER_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                 "--enable-unsafe-swiftshader", "--no-first-run", "--remote-allow-origins=*"]


class Browser:
    """One headless Chromium showing one page; `evaluate` runs an expression in it."""

    def __init__(self, url, timeout=60.0, idle=False):
        """idle: Chromium runs only when a CPU has nothing else to do (SCHED_IDLE), as the
        viewer does, so that it cannot take a CPU from a run it watches."""
        chromium = shutil.which("chromium")
        if chromium is None:
            raise AssertionError("chromium is missing: tools/dmpl setup installs it")
        self.profile = tempfile.mkdtemp(prefix="dmpl_chromium_")
        self.proc = subprocess.Popen(
            (["chrt", "--idle", "0"] if idle else []) +
            [chromium, *BROWSER_FLAGS, "--remote-debugging-port=0",
             f"--user-data-dir={self.profile}", "--window-size=320,240", url],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        port = self._devtools_port(timeout)
        page = self._page(port, url, timeout)
        self.loop = IOLoop()
        self.socket = self.loop.run_sync(lambda: websocket_connect(page["webSocketDebuggerUrl"]),
                                         timeout=timeout)
        self.next_id = 0

    def _devtools_port(self, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            line = self.proc.stderr.readline()
            found = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            if found:
                return int(found.group(1))
            if not line and self.proc.poll() is not None:
                break
        raise AssertionError("chromium did not open its DevTools port")

    @staticmethod
    def _page(port, url, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
                pages = [t for t in json.load(r) if t.get("type") == "page"]
            if pages:
                return pages[0]
            time.sleep(0.2)
        raise AssertionError(f"chromium shows no page for {url}")

    def evaluate(self, expression, timeout=30.0):
        """The JSON value of `expression` in the page (an exception in it is an AssertionError)."""
        self.next_id += 1
        request = {"id": self.next_id, "method": "Runtime.evaluate",
                   "params": {"expression": expression, "returnByValue": True}}

        async def call():
            await self.socket.write_message(json.dumps(request))
            while True:
                reply = json.loads(await self.socket.read_message())
                if reply.get("id") == request["id"]:
                    return reply

        reply = self.loop.run_sync(call, timeout=timeout)
        result = reply.get("result", {})
        if "exceptionDetails" in result or "error" in reply:
            raise AssertionError(f"page raised: {result.get('exceptionDetails') or reply}")
        return result["result"].get("value")

    def wait_for(self, expression, timeout, what):
        """Evaluates `expression` until it is true."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.evaluate(expression):
                return
            time.sleep(0.2)
        raise AssertionError(f"timed out after {timeout} s waiting for {what}")

    def close(self):
        self.socket.close()
        self.loop.close()
        self.proc.kill()
        self.proc.wait()
        self.proc.stderr.close()
        shutil.rmtree(self.profile, ignore_errors=True)
