"""Open a report in headless Chromium and check it, through the DevTools protocol over a pipe.

Chromium's ``--remote-debugging-pipe`` reads JSON commands on fd 3 and writes replies and events on
fd 4, each message ended by a NUL byte, so no port is opened and no websocket library is needed.
Networking is off twice: a proxy that does not exist (``--proxy-server=127.0.0.1:9``, loopback
only) and ``Network.emulateNetworkConditions(offline=True)`` before the page loads, so any request
the page made to the network would fail and be counted.
"""

from __future__ import annotations

import base64
import contextlib
import json
import os
import select
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

BROWSER_NAMES = ("chromium", "chromium-browser", "google-chrome", "chrome")

#: Checks run in the page: figure and table counts, figures' rendered sizes, and the texts each
#: figure's image says reach past its edges (``data-clipped``, from
#: ``stepframe.pipeline.reports.document.texts_outside``: matplotlib drops a glyph that would
#: cross the PNG's edge, so the cut cannot be told from the pixels).
PAGE_CHECK = """(() => {
  const figures = Array.from(document.querySelectorAll('figure img')).map(img => {
    const box = img.getBoundingClientRect();
    return {alt: img.alt, complete: img.complete, natural: [img.naturalWidth, img.naturalHeight],
            box: [box.width, box.height], clipped: img.dataset.clipped || ''};
  });
  const tables = Array.from(document.querySelectorAll('table')).map(t => ({
    headers: t.tHead ? t.tHead.rows[0].cells.length : 0,
    rows: t.tBodies.length ? t.tBodies[0].rows.length : 0,
    id: t.previousElementSibling ? t.previousElementSibling.id : ''}));
  return {figures, tables, title: document.title,
          height: document.documentElement.scrollHeight,
          width: document.documentElement.scrollWidth};
})()"""


def find_browser() -> str | None:
    """Path of a Chromium-family browser (``$STEPFRAME_BROWSER`` first), or None."""
    given = os.environ.get("STEPFRAME_BROWSER")
    if given:
        return shutil.which(given)
    for name in BROWSER_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


@dataclass
class PageCheck:
    """What the browser saw."""

    console_errors: list[str] = field(default_factory=list)
    failed_requests: list[str] = field(default_factory=list)
    figures: list[dict[str, Any]] = field(default_factory=list)
    tables: list[dict[str, Any]] = field(default_factory=list)
    title: str = ""
    screenshot: Path | None = None
    size_px: tuple[int, int] = (0, 0)


class _Pipe:
    def __init__(self, browser: str, profile: str) -> None:
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()

        def plumbing() -> None:  # in the child, before exec: fds 3 and 4 are the pipe
            # copy both ends above 4 first: a pipe end may itself be fd 3 or 4
            read_end, write_end = os.dup(to_child_r), os.dup(from_child_w)
            while read_end <= 4 or write_end <= 4:
                read_end, write_end = os.dup(read_end), os.dup(write_end)
            os.dup2(read_end, 3)
            os.dup2(write_end, 4)

        args = [
            browser,
            "--headless",
            "--remote-debugging-pipe",
            "--no-sandbox",  # CI runs as root, where the sandbox refuses to start
            "--disable-gpu",
            "--no-first-run",
            "--no-default-browser-check",
            "--disable-extensions",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--proxy-server=127.0.0.1:9",
            "--proxy-bypass-list=<-loopback>",
            "--hide-scrollbars",
            f"--user-data-dir={profile}",
            "about:blank",
        ]
        self._log = tempfile.TemporaryFile()  # noqa: SIM115 (closed in close())
        self.process = subprocess.Popen(
            args,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=self._log,
            close_fds=False,  # the pipe ends are duplicated onto fds 3 and 4 in the child
            preexec_fn=plumbing,
        )
        os.close(to_child_r)
        os.close(from_child_w)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict[str, Any]] = []

    def send(
        self,
        method: str,
        params: dict[str, Any] | None = None,
        session: str | None = None,
        timeout_s: float = 30.0,
    ) -> dict[str, Any]:
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        try:
            os.write(self._to_child, json.dumps(message).encode() + b"\0")
        except BrokenPipeError:
            raise RuntimeError(f"the browser exited: {self.log()}") from None
        deadline = time.monotonic() + timeout_s
        while True:
            reply = self._read(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return dict(reply.get("result", {}))
            self.events.append(reply)

    def wait_for(self, method: str, timeout_s: float = 30.0) -> dict[str, Any]:
        for event in self.events:
            if event.get("method") == method:
                return event
        deadline = time.monotonic() + timeout_s
        while True:
            event = self._read(deadline)
            self.events.append(event)
            if event.get("method") == method:
                return event

    def _read(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no reply from the browser")
            ready, _, _ = select.select([self._from_child], [], [], left)
            if ready:
                chunk = os.read(self._from_child, 1 << 20)
                if not chunk:
                    raise RuntimeError(f"the browser closed the pipe: {self.log()}")
                self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return dict(json.loads(message))

    def log(self) -> str:
        """The browser's stderr so far (last 2000 characters)."""
        self._log.seek(0)
        return self._log.read().decode(errors="replace")[-2000:]

    def close(self) -> None:
        with contextlib.suppress(OSError):  # the browser may have exited already
            close = {"id": 0, "method": "Browser.close"}
            os.write(self._to_child, json.dumps(close).encode() + b"\0")
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._to_child)
        os.close(self._from_child)
        self._log.close()


def check_page(html: Path, screenshot: Path, *, browser: str, width_px: int = 1200) -> PageCheck:
    """Load ``html`` from a file:// URL offline, collect errors, measure, take a full screenshot."""
    result = PageCheck()
    with tempfile.TemporaryDirectory(prefix="stepframe-browser-") as profile:
        pipe = _Pipe(browser, profile)
        try:
            targets = pipe.send("Target.getTargets")["targetInfos"]
            page = next(t for t in targets if t["type"] == "page")
            session = pipe.send(
                "Target.attachToTarget", {"targetId": page["targetId"], "flatten": True}
            )["sessionId"]
            for domain in ("Page", "Runtime", "Log", "Network"):
                pipe.send(f"{domain}.enable", session=session)
            pipe.send(
                "Network.emulateNetworkConditions",
                {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
                session=session,
            )
            pipe.send(
                "Emulation.setDeviceMetricsOverride",
                {"width": width_px, "height": 900, "deviceScaleFactor": 1, "mobile": False},
                session=session,
            )
            pipe.send("Page.navigate", {"url": html.resolve().as_uri()}, session=session)
            pipe.wait_for("Page.loadEventFired", timeout_s=60)
            state = pipe.send(
                "Runtime.evaluate",
                {"expression": PAGE_CHECK, "returnByValue": True},
                session=session,
            )["result"]["value"]
            result.figures = state["figures"]
            result.tables = state["tables"]
            result.title = state["title"]
            result.size_px = (int(state["width"]), int(state["height"]))
            shot = pipe.send(
                "Page.captureScreenshot",
                {
                    "format": "png",
                    "captureBeyondViewport": True,
                    "clip": {
                        "x": 0,
                        "y": 0,
                        "width": state["width"],
                        "height": state["height"],
                        "scale": 1,
                    },
                },
                session=session,
                timeout_s=60,
            )
            screenshot.write_bytes(base64.b64decode(shot["data"]))
            result.screenshot = screenshot
        finally:
            pipe.close()
    for event in pipe.events:
        method = event.get("method")
        params = event.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            result.console_errors.append(json.dumps(params.get("args")))
        elif method == "Runtime.exceptionThrown":
            result.console_errors.append(json.dumps(params.get("exceptionDetails")))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            result.console_errors.append(params["entry"].get("text", ""))
        elif method == "Network.loadingFailed":
            result.failed_requests.append(json.dumps(params))
    return result
