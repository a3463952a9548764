"""Workers die with their parent (issue 22): a signalled command leaves no process behind.

Each command runs as a process in its own process group (as a shell job, ``timeout`` or a CI
runner would start it); the signal goes to the parent alone, then the group is listed until it
is empty. Waits are polls with a deadline, never fixed sleeps that assume a speed.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from proc_util import SPIRALCAP

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="lists a process group through /proc"
)

SWEEP = [
    "sweep",
    "--optimize",
    "--over",
    "limits.power_W=300:3000:40",
    "--over",
    "limits.current_A=5:30:40",  # 1600 optimisations: far longer than the test waits
    "--workers",
    "2",
    "--csv",
    "out.csv",
]


def _group(pgid: int) -> list[int]:
    """Live (not zombie) processes of process group ``pgid``."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2 :].split()  # after "pid (comm) "
        if int(fields[2]) == pgid and fields[0] != "Z":
            pids.append(int(entry))
    return pids


def _poll(check, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if check():
            return True
        time.sleep(0.1)
    return check()


def _start(argv: list[str], cwd: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        argv,
        cwd=cwd,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, like a shell job
    )


def _stop_and_check(proc: subprocess.Popen[str], sig: int, workers: int, after_s: float) -> str:
    """Once ``workers`` children run and ``after_s`` seconds have passed since the start, send
    ``sig`` to the parent; the group must be empty within 20 s."""
    t0 = time.monotonic()
    started = _poll(lambda: len(_group(proc.pid)) >= 1 + workers or proc.poll() is not None, 120)
    assert started and proc.poll() is None, "the workers started and the command still runs"
    time.sleep(max(0.0, after_s - (time.monotonic() - t0)))  # the workers are in their tasks
    assert proc.poll() is None, "the command still runs when signalled"
    os.kill(proc.pid, sig)
    try:
        emptied = _poll(lambda: proc.poll() is not None and not _group(proc.pid), 20)
        assert emptied, f"processes of the group still alive 20 s later: {_group(proc.pid)}"
    finally:
        for pid in _group(proc.pid):  # do not leave them to the next test
            os.kill(pid, signal.SIGKILL)
        _, err = proc.communicate(timeout=30)  # reaps it and closes the pipe
    return err


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signalled_sweep_stops_its_workers(tmp_path: Path, sig: int) -> None:
    proc = _start([*SPIRALCAP, *SWEEP], tmp_path)
    err = _stop_and_check(proc, sig, workers=2, after_s=4.0)
    assert proc.returncode == 128 + sig, f"exit 128 + signal number ({err})"
    what = "interrupted" if sig == signal.SIGINT else f"stopped by {signal.Signals(sig).name}"
    assert err.strip().splitlines() == [f"spiralcap sweep: {what}"], err
    assert list(tmp_path.iterdir()) == [], "no output, not even a partial one"


@pytest.mark.slow
def test_workers_of_a_killed_parent_die_too(tmp_path: Path) -> None:
    """SIGKILL cannot be handled: the workers end through PR_SET_PDEATHSIG."""
    proc = _start([*SPIRALCAP, *SWEEP], tmp_path)
    _stop_and_check(proc, signal.SIGKILL, workers=2, after_s=4.0)
    assert proc.returncode == -signal.SIGKILL


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL])
def test_forked_children_die_with_the_command(tmp_path: Path, sig: int) -> None:
    """The report's forked workers (``map_forked``, ``Forked``), as the command runs them."""
    script = textwrap.dedent(
        """
        import sys, time
        from spiralcap.parallel import Forked, map_forked, stop_on_signals
        stop_on_signals()
        try:
            job = Forked(time.sleep, 600)
            map_forked(lambda i: time.sleep(600), list(range(4)), 3)
        except KeyboardInterrupt as exc:
            print("stopped", exc.signum, file=sys.stderr)
            sys.exit(1)
        """
    )
    proc = _start([sys.executable, "-c", script], tmp_path)
    err = _stop_and_check(proc, sig, workers=3, after_s=1.0)
    if sig == signal.SIGTERM:
        assert err.strip() == f"stopped {int(sig)}", err
