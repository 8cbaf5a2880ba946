"""``rotarydryer app`` stops its Streamlit server when it is stopped (SIGTERM, SIGINT): the
server child gets the signal, the port closes, no process is left behind."""

import os
import signal
import socket
import subprocess
import sys
import time

import pytest

pytest.importorskip("streamlit")
psutil = pytest.importorskip("psutil")

from .browser_support import free_port, wait_until_serving  # noqa: E402 - no browser needed

pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX signals")


def _listening(port) -> bool:
    with socket.socket() as s:
        s.settimeout(0.5)
        return s.connect_ex(("127.0.0.1", port)) == 0


def _start(tmp_path):
    port = free_port()
    log = open(tmp_path / "app.log", "wb")
    proc = subprocess.Popen([sys.executable, "-m", "rotarydryer", "app", "--port", str(port)], stdout=log,
                            stderr=subprocess.STDOUT)
    wait_until_serving(f"http://127.0.0.1:{port}", proc, tmp_path / "app.log", what="rotarydryer app")
    children = psutil.Process(proc.pid).children(recursive=True)
    assert children, "no server child process"
    return proc, port, children, log


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_signal_to_rotarydryer_app_stops_the_server(tmp_path, sig):
    proc, port, children, log = _start(tmp_path)
    try:
        t0 = time.monotonic()
        proc.send_signal(sig)
        proc.wait(timeout=10)
        gone, alive = psutil.wait_procs(children, timeout=max(0.1, 10 - (time.monotonic() - t0)))
        assert not alive, f"server child left running: {alive}"
        deadline = time.monotonic() + 5
        while _listening(port) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not _listening(port), f"port {port} still listening"
        assert time.monotonic() - t0 < 10
        assert proc.returncode in (0, 128 + sig), proc.returncode
    finally:
        for p in [proc, *children]:
            try:
                p.kill()
            except (OSError, psutil.NoSuchProcess):
                pass
        proc.wait()
        log.close()
