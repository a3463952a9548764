"""``--dask`` to a scheduler with no workers (issue 22): a one-line error, exit 2, in bounded time.

A scheduler that answers but has no worker (none started yet), and one whose only worker is
killed mid-run: the command waits :data:`spiralcap.dask_cluster.NO_WORKERS_S` seconds for a worker,
then says so; it never waits forever. The command runs as a process (its exit status and stderr
are the promise), with that wait set to :data:`WAIT_S` (the bounded wait and its message are
tested, not the product's 10 s); the scheduler is a LocalCluster in this process, on ports the OS
picks.
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from proc_util import SPIRALCAP

distributed = pytest.importorskip("distributed")

#: Seconds without a worker the commands here wait before giving up.
WAIT_S = 1.0
#: ``spiralcap`` as a process, its wait for a worker set to :data:`WAIT_S`.
COMMAND = [
    sys.executable,
    "-c",
    f"import spiralcap.dask_cluster as d; d.NO_WORKERS_S = {WAIT_S}\n{SPIRALCAP[-1]}",
]

SWEEP = ["sweep", "--optimize", "--over", "limits.power_W=300:3000:40"]
#: Bound on the whole run: the wait for workers plus start-up, with room for a loaded machine.
BOUND_S = WAIT_S + 120


def _cluster(n_workers: int) -> distributed.LocalCluster:
    return distributed.LocalCluster(
        n_workers=n_workers,
        processes=True,  # tcp:// (the scheduler runs here; no worker is started)
        host="127.0.0.1",
        scheduler_port=0,
        dashboard_address=":0",  # a port the OS picks (8787 may be taken; None means 8787)
    )


def _check_one_line(proc: subprocess.CompletedProcess[str], address: str) -> None:
    assert proc.returncode == 2, f"exit 2, got {proc.returncode}: {proc.stderr[-800:]}"
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert lines[0].startswith("spiralcap sweep: error: --dask"), lines[0]
    assert address in lines[0] and "workers" in lines[0], lines[0]


@pytest.mark.slow
def test_a_scheduler_without_workers_is_an_error_not_a_hang(tmp_path: Path) -> None:
    with _cluster(0) as cluster:
        address = cluster.scheduler_address
        t0 = time.monotonic()
        proc = subprocess.run(
            [*COMMAND, *SWEEP, "--dask", address, "--csv", "out.csv"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=BOUND_S,  # a hang fails here
        )
        took = time.monotonic() - t0
    _check_one_line(proc, address)
    assert took >= WAIT_S, "it waited for a worker to join before giving up"
    assert f"{WAIT_S:g} s" in proc.stderr, "and says how long"
    assert list(tmp_path.iterdir()) == [], "nothing written"


@pytest.mark.slow
def test_a_cluster_whose_workers_all_die_mid_run_is_an_error(tmp_path: Path) -> None:
    with _cluster(0) as cluster:
        address = cluster.scheduler_address
        worker = subprocess.Popen(  # a worker process of its own, to kill
            [
                sys.executable,
                "-m",
                "distributed.cli.dask_worker",
                address,
                "--no-nanny",
                "--nthreads",
                "1",
                "--no-dashboard",
                "--host",
                "127.0.0.1",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        try:
            client = distributed.Client(address, set_as_default=False)
            try:
                client.wait_for_workers(1, timeout=120)
                cmd = subprocess.Popen(
                    [
                        *COMMAND,
                        "sweep",
                        "--optimize",
                        "--over",
                        "limits.power_W=300:3000:40",
                        "--over",
                        "limits.current_A=5:30:40",  # long enough to be cut off mid-run
                        "--dask",
                        address,
                        "--csv",
                        "out.csv",
                    ],
                    cwd=tmp_path,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.PIPE,
                    text=True,
                )
                deadline = time.monotonic() + 120
                while not client.processing() or not any(client.processing().values()):
                    assert time.monotonic() < deadline and cmd.poll() is None, "tasks started"
                    time.sleep(0.1)
            finally:
                client.close()
            worker.kill()  # the only worker dies mid-run
            worker.wait(30)
            _, err = cmd.communicate(timeout=BOUND_S)  # a hang fails here
        finally:
            if worker.poll() is None:
                worker.kill()
                worker.wait(30)
    _check_one_line(subprocess.CompletedProcess(cmd.args, cmd.returncode, "", err), address)
    assert list(tmp_path.iterdir()) == [], "nothing written"
