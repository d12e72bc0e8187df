#!/usr/bin/env python3
"""`linx view` against hostile clients on loopback (issue 43): byte ranges are answered by the
file's size (416 past the end, exact lengths otherwise), and normal requests are served while
60 clients trickle their headers a byte a second and 400 more hold idle connections, whether
they come from other addresses (127.0.0.2, 127.0.0.3) or from the user's own 127.0.0.1.
The slow connections are ended by the server within its request deadline (4 s).

Usage: test_view_clients.py LINX EXAMPLES
"""
import http.client
import json
import os
import re
import resource
import socket
import subprocess
import sys
import tempfile
import threading
import time

linx, examples = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def request(port, path, headers=None, timeout=5.0):
    """(status, headers, body, seconds) of one GET from 127.0.0.1."""
    start = time.monotonic()
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        c.request("GET", path, headers={"Host": f"127.0.0.1:{port}", **(headers or {})})
        r = c.getresponse()
        body = r.read()
        return r.status, dict(r.getheaders()), body, time.monotonic() - start
    except (OSError, http.client.HTTPException, OverflowError) as e:  # no answer, or a bad one
        return f"{type(e).__name__}: {e}", {}, b"", time.monotonic() - start
    finally:
        c.close()


def ranges(port, whole):
    n = len(whole)
    big = 99999999999999
    cases = [  # Range header, status, body expected (None: not checked), Content-Range
        (f"bytes={big}-", 416, None, f"bytes */{n}"),
        (f"bytes={n}-", 416, None, f"bytes */{n}"),
        (f"bytes={n}-{n + 10}", 416, None, f"bytes */{n}"),
        ("bytes=-0", 416, None, f"bytes */{n}"),
        ("bytes=0-", 206, whole, f"bytes 0-{n - 1}/{n}"),
        (f"bytes=10-{big}", 206, whole[10:], f"bytes 10-{n - 1}/{n}"),
        ("bytes=-5", 206, whole[-5:], f"bytes {n - 5}-{n - 1}/{n}"),
        (f"bytes=-{big}", 206, whole, f"bytes 0-{n - 1}/{n}"),
        ("bytes=3-7", 206, whole[3:8], f"bytes 3-7/{n}"),
        (f"bytes=0-0,{big}-", 206, whole[0:1], f"bytes 0-0/{n}"),  # the other is dropped
        ("bytes=99999999999999999999999-", 416, None, None),  # overflows: cpp-httplib's 416
        ("bytes=7-3", 416, None, None),
        ("bytes=0-0,2-2,4-4,6-6,8-8", 416, None, None),  # at most four ranges
    ]
    for header, status, body, content_range in cases:
        got, headers, data, _ = request(port, "/run/bodies.csv", {"Range": header})
        check(got == status, f"Range: {header}: HTTP {got}, expected {status}")
        check(int(headers.get("Content-Length", -1)) == len(data) < 1000 or body is not None,
              f"Range: {header}: a refusal of {headers.get('Content-Length')} bytes")
        if body is not None:
            check(data == body, f"Range: {header}: {len(data)} bytes, expected {len(body)}")
            check(int(headers.get("Content-Length", -1)) == len(data),
                  f"Range: {header}: Content-Length {headers.get('Content-Length')}")
        if content_range is not None:
            check(headers.get("Content-Range") == content_range,
                  f"Range: {header}: Content-Range {headers.get('Content-Range')}")
    # Several ranges: one multipart answer holding each.
    got, headers, data, _ = request(port, "/run/bodies.csv", {"Range": "bytes=0-3,10-13"})
    check(got == 206 and headers.get("Content-Type", "").startswith("multipart/byteranges")
          and whole[0:4] in data and whole[10:14] in data,
          f"two ranges: HTTP {got} {headers.get('Content-Type')}")


def connect(port, source):
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind((source, 0))
    s.setblocking(True)
    s.connect(("127.0.0.1", port))
    return s


def attack(port, source_slow, source_idle, label):
    """60 trickling and 400 idle connections; normal requests meanwhile; all ended in time."""
    slow = [connect(port, source_slow) for _ in range(60)]
    idle = [connect(port, source_idle) for _ in range(400)]
    head = f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Slow: {'a' * 40}\r\n".encode()
    stop = threading.Event()

    def trickle():
        for i in range(len(head)):
            for s in slow:
                try:
                    s.send(head[i:i + 1])
                except OSError:
                    pass
            if stop.wait(1.0):
                return

    t = threading.Thread(target=trickle)
    t.start()
    log(f"{label}: {len(slow)} trickling, {len(idle)} idle connections")
    time.sleep(0.5)
    try:
        for k in range(3):  # over the attack's first seconds
            status, _, body, seconds = request(port, "/run/manifest.json", timeout=10)
            check(status == 200 and b"bodies.csv" in body, f"{label}: normal request: HTTP {status}")
            check(seconds < 2.0, f"{label}: normal request {k} took {seconds:.2f} s")
            time.sleep(1.0)
            log(f"{label}: normal request {k} answered in {seconds:.3f} s")
        # The server ends the slow and idle connections within its deadline (4 s from accept).
        time.sleep(2.5)
        open_ones = 0
        for s in slow + idle:
            s.settimeout(0.01)
            try:
                if s.recv(1) != b"":
                    open_ones += 1
            except socket.timeout:
                open_ones += 1
            except OSError:
                pass
        check(open_ones == 0, f"{label}: {open_ones} slow or idle connections still open after 6 s")
    finally:
        stop.set()
        t.join()
        for s in slow + idle:
            s.close()


def log(what):
    print(f"{time.monotonic() - t0:6.2f} s: {what}", flush=True)


t0 = time.monotonic()


def main():
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (min(max(soft, 4096), hard), hard))
    with tempfile.TemporaryDirectory() as work:
        # The folder's name reaches the page (its title) through the manifest's JSON.
        folder = "run`touch CANARY`<img src=x onerror=alert(1)>\"'\\ \u00e9"
        run = os.path.join(work, folder)
        subprocess.run([linx, "run", os.path.join(examples, "pendulum.json"), "--out", run,
                        "--duration", "0.1"], check=True, stdout=subprocess.DEVNULL)
        view = subprocess.Popen([linx, "view", run, "--port", "0"], stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True)
        try:
            port = int(re.search(r"127\.0\.0\.1:(\d+)/", view.stdout.readline()).group(1))
            status, _, body, _ = request(port, "/run/manifest.json")
            manifest = json.loads(body)
            check(status == 200 and manifest["name"] == folder,
                  f"manifest: HTTP {status}: {body!r}")
            whole = open(os.path.join(run, "bodies.csv"), "rb").read()
            status, _, body, _ = request(port, "/run/bodies.csv")
            check(status == 200 and body == whole, f"bodies.csv: HTTP {status}")
            ranges(port, whole)
            log("ranges checked")
            # A body the viewer would have to hold: refused at once (it takes none).
            s = connect(port, "127.0.0.1")
            s.sendall(f"POST / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
                      "Content-Length: 1000000000\r\n\r\nabc".encode())
            s.settimeout(5)
            check(s.recv(100).startswith(b"HTTP/1.1 413 "), "a 1 GB body is not refused")
            s.close()
            attack(port, "127.0.0.2", "127.0.0.3", "other addresses")
            log("attack from other addresses survived")
            attack(port, "127.0.0.1", "127.0.0.1", "the same address")
            log("attack from the same address survived")
            check(view.poll() is None, "linx view stopped during the attack")
        finally:
            view.terminate()
            view.wait(timeout=10)
            log("linx view stopped")
    if failures:
        sys.exit(f"{len(failures)} failures")
    print("view clients: ok")


main()
