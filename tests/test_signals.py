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


def _ipopt_loaded(pid: int) -> bool:
    """Whether process ``pid`` has mapped CasADi's IPOPT plugin: it builds its first solver,
    and its solves follow (the plugin is loaded at the first ``nlpsol``)."""
    try:
        return "ipopt" in Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return False


def _ready(proc: subprocess.Popen[str], workers: int, solving: bool) -> bool:
    """``workers`` children of ``proc`` run (``solving``: and have each loaded IPOPT)."""
    children = [p for p in _group(proc.pid) if p != proc.pid]
    if solving:
        children = [p for p in children if _ipopt_loaded(p)]
    return len(children) >= workers


def _stop_and_check(proc: subprocess.Popen[str], sig: int, workers: int, after_s: float) -> str:
    """Once ``workers`` children run, wait ``after_s`` seconds more and send ``sig`` to the
    parent; the group must be empty within 20 s."""
    return _stop_all_and_check([(proc, sig, workers, after_s)])[0]


def _stop_all_and_check(
    jobs: list[tuple[subprocess.Popen[str], int, int, float]], solving: bool = False
) -> list[str]:
    """:func:`_stop_and_check` for several commands running at once, each job ``(proc, sig,
    workers, after_s)``: each is signalled ``after_s`` seconds after its workers run
    (``solving``: after each has loaded IPOPT, so they are in their tasks); every group must be
    empty within 20 s of its signal. The stderr of each, in order."""
    t0 = time.monotonic()
    ready: dict[int, float] = {}  # job -> when its workers were first seen ready
    sent: set[int] = set()
    try:
        while len(sent) < len(jobs):
            assert time.monotonic() - t0 < 120.0, "the workers started within 120 s"
            now = time.monotonic()
            for i, (proc, sig, workers, after_s) in enumerate(jobs):
                if i in sent:
                    continue
                assert proc.poll() is None, "the command still runs until it is signalled"
                if i not in ready:
                    if _ready(proc, workers, solving):
                        ready[i] = now
                elif now - ready[i] >= after_s:
                    os.kill(proc.pid, sig)
                    sent.add(i)
            time.sleep(0.05)
        for proc, sig, _, _ in jobs:
            emptied = _poll(lambda p=proc: p.poll() is not None and not _group(p.pid), 20)
            assert emptied, (
                f"{signal.Signals(sig).name}: processes of the group still alive 20 s later"
            )
    finally:
        for proc, _, _, _ in jobs:
            for pid in _group(proc.pid):  # do not leave them to the next test
                os.kill(pid, signal.SIGKILL)
        errs = [proc.communicate(timeout=30)[1] for proc, _, _, _ in jobs]  # reaps, closes pipes
    return errs


@pytest.mark.slow
def test_a_signalled_sweep_stops_its_workers(tmp_path: Path) -> None:
    """SIGTERM, SIGHUP, SIGINT to a sweep on two workers, and SIGKILL (which cannot be handled:
    the workers end through PR_SET_PDEATHSIG), four sweeps running at once, each in its own
    folder, each signalled 0.5 s after both its workers have loaded IPOPT (they are in their
    solves): no process left, exit 128 + signal number with one line saying so, no output."""
    sigs = [signal.SIGTERM, signal.SIGHUP, signal.SIGINT, signal.SIGKILL]
    folders = [tmp_path / signal.Signals(sig).name for sig in sigs]
    jobs = []
    for sig, folder in zip(sigs, folders):
        folder.mkdir()
        jobs.append((_start([*SPIRALCAP, *SWEEP], folder), sig, 2, 0.5))
    errs = _stop_all_and_check(jobs, solving=True)
    for (proc, sig, _, _), err, folder in zip(jobs, errs, folders):
        name = signal.Signals(sig).name
        assert list(folder.iterdir()) == [], f"{name}: no output, not even a partial one"
        if sig == signal.SIGKILL:
            assert proc.returncode == -signal.SIGKILL
            continue
        assert proc.returncode == 128 + sig, f"{name}: exit 128 + signal number ({err})"
        what = "interrupted" if sig == signal.SIGINT else f"stopped by {name}"
        assert err.strip().splitlines() == [f"spiralcap sweep: {what}"], err


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL])
def test_pool_workers_die_with_the_command(tmp_path: Path, sig: int) -> None:
    """The workers of a process pool (the report's forked drawing, sizing's neighbours), as the
    command runs them: a closure each (:func:`spiralcap.parallel.inherited`)."""
    script = textwrap.dedent(
        """
        import sys, time
        from spiralcap.parallel import inherited, process_pool
        from spiralcap.stopping import stop_on_signals
        stop_on_signals()
        try:
            with inherited(lambda i: time.sleep(600)) as nap, process_pool(3) as pool:
                list(pool.map(nap, range(4)))
        except KeyboardInterrupt as exc:
            print("stopped", exc.signum, file=sys.stderr)
            sys.exit(1)
        """
    )
    proc = _start([sys.executable, "-c", script], tmp_path)
    err = _stop_and_check(proc, sig, workers=3, after_s=0.3)
    if sig == signal.SIGTERM:
        assert err.strip() == f"stopped {int(sig)}", err


#: A re-optimising sweep without --workers: every solve runs in the command's own process, so
#: a signal mostly lands inside IPOPT. (The grid is 40 x 40 points so that the command still
#: runs well after the last signal.)
LONG_SWEEP = [
    "sweep",
    "--optimize",
    "--over",
    "limits.power_W=300:3000:40",
    "--over",
    "limits.current_A=5:30:40",
    "--csv",
    "out.csv",
]


@pytest.mark.slow
def test_sigterm_inside_ipopt_ends_the_sweep_within_5_s(tmp_path: Path) -> None:
    """SIGTERM 0.5, 1.25 and 2 s after each sweep has loaded IPOPT (three sweeps running at
    once, each in its own folder: a signal early in the solves and later ones) reaches a solve
    in IPOPT (CasADi turns it into a status the NLP layer raises as
    :class:`optimize.nlp.SolveInterrupted`): each command ends within 5 s, exit 128 + 15, says
    so on its last stderr line, writes nothing and leaves no process. The schedule starts when
    the solver exists, not at a fixed time, so a slow runner still signals inside the solves."""
    afters = [0.5, 1.25, 2.0]
    folders = [tmp_path / f"at_{a}s" for a in afters]
    for folder in folders:
        folder.mkdir()
    procs = [_start([*SPIRALCAP, *LONG_SWEEP], folder) for folder in folders]
    t0 = time.monotonic()
    ready: dict[int, float] = {}  # job -> when IPOPT was first seen loaded
    sent: dict[int, float] = {}  # job -> when its SIGTERM went
    ended: dict[int, float] = {}  # job -> when its group was first seen empty
    try:
        while len(ended) < len(procs) and time.monotonic() - t0 < 120.0:
            now = time.monotonic()
            for i, (proc, after_s) in enumerate(zip(procs, afters)):
                if i not in ready:
                    if _ipopt_loaded(proc.pid):
                        ready[i] = now
                    else:
                        assert proc.poll() is None, f"the sweep ended before IPOPT ({i})"
                elif i not in sent and now - ready[i] >= after_s:
                    assert proc.poll() is None, f"the sweep still runs {after_s} s into IPOPT"
                    os.kill(proc.pid, signal.SIGTERM)
                    sent[i] = time.monotonic()
                elif i in sent and i not in ended and proc.poll() is not None:
                    if not _group(proc.pid):
                        ended[i] = time.monotonic()
            time.sleep(0.05)
    finally:
        for proc in procs:
            if proc.poll() is None:
                os.kill(proc.pid, signal.SIGKILL)
            for pid in _group(proc.pid):
                os.kill(pid, signal.SIGKILL)
        errs = [proc.communicate(timeout=30)[1] for proc in procs]  # reaps, closes the pipes
    for i, (proc, after_s, folder, err) in enumerate(zip(procs, afters, folders, errs)):
        assert i in sent and sent[i] - ready[i] >= after_s, f"SIGTERM sent {after_s} s into IPOPT"
        took = ended.get(i, float("inf")) - sent[i]
        assert took <= 5.0, f"still running 5 s after SIGTERM at {after_s} s ({took:.1f} s)"
        assert proc.returncode == 128 + signal.SIGTERM, f"{after_s} s: exit 143 ({err})"
        assert err.strip().splitlines()[-1] == "spiralcap sweep: stopped by SIGTERM", err
        assert list(folder.iterdir()) == [], f"{after_s} s: nothing written ({took:.1f} s after)"


def _first_child(pid: int, timeout_s: float) -> int | None:
    """A live child process of ``pid`` (a pool worker), once one runs."""
    found: list[int] = []

    def look() -> bool:
        found[:] = [p for p in _group(pid) if p != pid]
        return bool(found) or _group(pid) == []

    _poll(look, timeout_s)
    return found[0] if found else None


@pytest.mark.slow
@pytest.mark.parametrize(
    ("argv", "what"),
    [
        (
            [
                "uncertainty",
                "--set",
                "tissue.uncertainty.scale_sigma_log=0.3",
                "--samples",
                "4000000",
                "--workers",
                "2",
                "--plot",
                "out.png",
            ],
            "uncertainty",
        ),
        (
            [
                "sweep",
                "--optimize",
                "--over",
                "limits.power_W=300:3000:40",
                "--over",
                "limits.current_A=5:30:40",
                "--workers",
                "2",
                "--csv",
                "out.csv",
            ],
            "sweep",
        ),
    ],
    ids=["uncertainty worker", "sweep worker"],
)
def test_a_worker_killed_from_outside_is_one_line(tmp_path: Path, argv: list[str], what: str):
    """SIGKILL of an uncertainty or a sweep worker: one line on stderr naming what happened, a
    non-zero exit, no traceback, nothing written, no process left. (Sizing has no helper
    process since issue 27: ``spiralcap optimize`` runs it here.)"""
    proc = subprocess.Popen(
        [*SPIRALCAP, *argv],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        child = _first_child(proc.pid, 60)
        assert child is not None, "a worker process started"
        os.kill(child, signal.SIGKILL)
        out, err = proc.communicate(timeout=60)
    finally:
        for pid in _group(proc.pid):
            os.kill(pid, signal.SIGKILL)
    assert proc.returncode not in (0, None), f"a non-zero exit ({err})"
    lines = err.strip().splitlines()
    assert lines == [
        f"spiralcap {what}: error: a worker process was killed from outside; no result written"
    ], err
    assert "Traceback" not in err and out == "", "no traceback, no output"
    assert list(tmp_path.iterdir()) == [], "nothing written"
    assert _poll(lambda: not _group(proc.pid), 10), "no process left"


def test_a_lost_stop_request_still_ends_a_sweep_after_its_point(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A :class:`spiralcap.stopping.Terminated` raised where nothing passes it on (a finaliser,
    a callback from compiled code: printed as ignored) still ends a re-optimising sweep: each
    point re-raises a stop request once its solve is done (``stopping.raise_if_requested``)."""
    from spiralcap import stopping
    from spiralcap.design import load_design
    from spiralcap.sweep import parse_over, sweep

    monkeypatch.setattr(stopping, "_REQUESTED", [int(signal.SIGTERM)])  # the lost request
    # a fresh run: an earlier in-process command of this worker may have committed its outputs
    monkeypatch.setattr(stopping, "_COMMIT", [False, False, False, False])
    with pytest.raises(stopping.Terminated) as stopped:
        sweep(load_design(), [parse_over("limits.power_W=300:3000:3")], optimize=True)
    assert stopped.value.signum == signal.SIGTERM, "the request's own signal"
