#!/usr/bin/python3
"""Loads a page in headless Chromium and reads it over the DevTools protocol, for the dashboard test.

Usage: cdp_page.py CHROMIUM URL PROFILE_DIR STEP...   where each STEP is SECONDS=EXPRESSION: wait that
long (the page keeps running), then evaluate the JavaScript expression in the page; a STEP
SECONDS=!COMMAND instead runs COMMAND (split as a shell would, no shell) at that moment, with its
exit status as the step's value (e.g. to kill a board while the page is open); a STEP SECONDS=@FILE
writes a screenshot of the page to FILE (PNG; the step's value is its size in bytes).

The protocol runs over a pipe (--remote-debugging-pipe: fd 3 to Chromium, fd 4 back, NUL-terminated
JSON messages), so no websocket client is needed. Prints one JSON object:
{"values": [<value of each step>], "errors": [<console errors, uncaught exceptions, failed loads>]}
and exits 0; exits 2 if Chromium or the protocol fails.
"""
import base64
import json
import os
import select
import shlex
import subprocess
import sys
import time


class Browser:
    def __init__(self, chromium, profile):
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()

        def wire():  # in the child: its fd 3 reads our commands, its fd 4 carries the answers
            a = os.dup(to_child_r)
            b = os.dup(from_child_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [chromium, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--no-default-browser-check", "--disable-extensions", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--remote-debugging-pipe",
             "--user-data-dir=" + profile, "about:blank"],
            preexec_fn=wire, close_fds=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_child_r)
        os.close(from_child_w)
        self.buffer = b""
        self.next_id = 0
        self.events = []

    def send(self, method, params=None, session=None):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.to_child, json.dumps(message).encode() + b"\0")
        return self.next_id

    def read(self, timeout):
        """One message, or None after `timeout` seconds."""
        deadline = time.monotonic() + timeout
        while b"\0" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            ready, _, _ = select.select([self.from_child], [], [], left)
            if ready:
                chunk = os.read(self.from_child, 65536)
                if not chunk:
                    raise RuntimeError("chromium closed the protocol pipe")
                self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, params=None, session=None, timeout=20):
        wanted = self.send(method, params, session)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            message = self.read(deadline - time.monotonic())
            if message is None:
                break
            if message.get("id") == wanted:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})
            self.events.append(message)
        raise RuntimeError(f"{method}: no answer within {timeout} s")

    def pump(self, seconds):
        deadline = time.monotonic() + seconds
        while True:
            message = self.read(max(deadline - time.monotonic(), 0))
            if message is None:
                return
            self.events.append(message)

    def close(self):
        try:
            self.send("Browser.close")
            self.proc.wait(timeout=10)
        except Exception:
            self.proc.kill()
            self.proc.wait()


def errors_of(events):
    out = []
    for e in events:
        method, p = e.get("method"), e.get("params", {})
        if method == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            out.append("uncaught: " + d.get("exception", {}).get("description", d.get("text", "?")))
        elif method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            out.append("console.error: " + " ".join(str(a.get("value", a.get("description", ""))) for a in p["args"]))
        elif method == "Log.entryAdded" and p["entry"]["level"] == "error":
            out.append(f"log ({p['entry']['source']}): {p['entry']['text']} {p['entry'].get('url', '')}")
    return out


def main():
    chromium, url, profile = sys.argv[1:4]
    steps = []
    for step in sys.argv[4:]:
        seconds, expression = step.split("=", 1)
        steps.append((float(seconds), expression))
    browser = Browser(chromium, profile)
    try:
        target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime.enable", "Log.enable", "Page.enable"):
            browser.call(domain, session=session)
        browser.call("Page.navigate", {"url": url}, session=session)
        values = []
        for seconds, expression in steps:
            browser.pump(seconds)
            if expression.startswith("!"):
                values.append(subprocess.run(shlex.split(expression[1:]), check=False).returncode)
                continue
            if expression.startswith("@"):
                shot = browser.call("Page.captureScreenshot", {"format": "png"}, session=session)
                png = base64.b64decode(shot["data"])
                with open(expression[1:], "wb") as f:
                    f.write(png)
                values.append(len(png))
                continue
            result = browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True},
                                  session=session)
            if "exceptionDetails" in result:
                values.append({"exception": result["exceptionDetails"].get("text", "?")})
            else:
                values.append(result["result"].get("value"))
        browser.pump(0.2)
        print(json.dumps({"values": values, "errors": errors_of(browser.events)}))
    except Exception as e:  # the test reports it; chromium must not be left running
        print(f"cdp_page: {e}", file=sys.stderr)
        sys.exit(2)
    finally:
        browser.close()


if __name__ == "__main__":
    main()
