"""`karstgen view DIR --serve` as a user runs it (the README exempts it from test_readme.py
because it serves until stopped): it writes the viewer, prints the URL it serves on, answers
the page and its data over HTTP on 127.0.0.1 until it is stopped, and a port in use is a bad
input (exit 2, with the flag that avoids it)."""

import os
import queue
import re
import signal
import socket
import subprocess
import threading
import urllib.error
import urllib.request

import pytest

from conftest import TINY, karstgen_command

URL = re.compile(r"serving .* at (http://127\.0\.0\.1:\d+/?)")


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("view-serve") / "tiny"
    karstgen_command("run", TINY, "--out", out)
    return out


def served_url(process, timeout=300):
    """The URL the server prints, read from its stdout on a thread so a silent server fails
    the test after `timeout` seconds instead of hanging it."""
    lines = queue.Queue()

    def read():
        for line in process.stdout:
            lines.put(line)
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    while True:
        line = lines.get(timeout=timeout)
        assert line is not None, f"the server stopped: {process.stderr.read()}"
        found = URL.search(line)
        if found:
            return found.group(1).rstrip("/")


def get(url):
    try:
        with urllib.request.urlopen(url, timeout=30) as reply:
            return reply.status, reply.headers.get("Content-Type"), reply.read()
    except urllib.error.HTTPError as error:
        return error.code, error.headers.get("Content-Type"), error.read()


def test_serve_answers_the_viewer_on_loopback_until_stopped(tiny_run):
    binary = os.environ["KARSTGEN_BIN"]
    process = subprocess.Popen(
        [binary, "view", str(tiny_run), "--serve", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = served_url(process)
        status, kind, page = get(url + "/")
        assert (status, kind) == (200, "text/html; charset=utf-8")
        assert b"<html" in page.lower()
        # Every file the page names beside it is served, with its type.
        names = set(re.findall(rb'(?:src|href)="([\w./-]+\.(?:js|json|css|glb))"', page))
        assert names, "the page names its scripts and data"
        for name in sorted(names):
            status, kind, body = get(f"{url}/{name.decode()}")
            assert status == 200 and body, f"{name}: {status}"
        status, kind, body = get(url + "/data/run.json")
        assert (status, kind) == (200, "application/json") and body.startswith(b"{")
        assert get(url + "/no-such-file.json")[0] == 404
        assert get(url + "/../../etc/passwd")[0] in (400, 403, 404)
        assert process.poll() is None, "serves until stopped"
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    assert (tiny_run / "view" / "index.html").is_file()


def test_a_port_in_use_exits_2_naming_another_port(tiny_run):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = karstgen_command("view", tiny_run, "--serve", "--port", port, check=False)
    assert result.returncode == 2, result.stderr
    assert f"port {port}" in result.stderr and "--port 0" in result.stderr, result.stderr
