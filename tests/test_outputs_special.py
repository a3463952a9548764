"""Outputs that are not regular files, and full disks (issue 22), through the command as a process
(stdout itself, and FIFOs: the process's timeout is the guard against a hang) or in-process
(``spiralcap.cli.main``: the same code opens, writes and closes the files, and pytest's
``filterwarnings = error`` fails a run on any warning).

A character device or FIFO given as an output is written into, never replaced by a file; a block
device or socket is refused (exit 2 naming the option); a full device (``/dev/full``) is an
error (exit 2, one line), never success; commands with two outputs write both or neither.
"""

from __future__ import annotations

import os
import socket
import stat
import subprocess
from pathlib import Path

import pytest
from _te_memo import solved_once  # noqa: F401 (the fixture)
from cli_outcome import run
from proc_util import SPIRALCAP

ROOT = Path(__file__).resolve().parents[1]
CSV = str(ROOT / "examples" / "bench_synthetic_sample2.csv")
WAVEFORMS = ["waveforms", "--heading", "1,0,0", "--dwell-s", "1"]


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*SPIRALCAP, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def _here(
    args: list[str], cwd: Path, monkeypatch: pytest.MonkeyPatch
) -> subprocess.CompletedProcess[str]:
    """``spiralcap args`` in-process in ``cwd``, its outcome in the form :func:`_run` gives."""
    monkeypatch.chdir(cwd)
    rc, out, err = run(args)
    return subprocess.CompletedProcess(args, rc, out, err)


def _one_line_error(proc: subprocess.CompletedProcess[str], *needles: str) -> str:
    assert proc.returncode == 2, f"exit 2 expected, got {proc.returncode}: {proc.stderr}"
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for n in needles:
        assert n in lines[0], f"the message names {n!r}: {lines[0]}"
    return lines[0]


@pytest.mark.usefixtures("solved_once")  # the built-in optimum, once (tests/_te_memo.py)
def test_output_to_a_character_device_stays_a_device(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    dev = tmp_path / "null.toml"
    null = os.stat("/dev/null")
    try:
        os.mknod(dev, stat.S_IFCHR | 0o666, null.st_rdev)  # a copy of /dev/null
    except PermissionError:
        pytest.skip("creating a device node needs root")
    proc = _here(["optimize", "-o", str(dev)], tmp_path, monkeypatch)
    assert proc.returncode == 0, proc.stderr
    mode = os.lstat(dev).st_mode
    assert stat.S_ISCHR(mode), "the device node is written into, not replaced by a file"
    assert os.stat(dev).st_rdev == null.st_rdev
    assert sorted(p.name for p in tmp_path.iterdir()) == ["null.toml"], "no temporary file left"


@pytest.mark.usefixtures("solved_once")
@pytest.mark.parametrize("command", [["init", "--force"], ["optimize", "-o"]])
def test_a_full_device_is_an_error_not_success(
    tmp_path: Path, command: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    proc = _here([*command, "/dev/full"], tmp_path, monkeypatch)
    _one_line_error(proc, "/dev/full", "No space left")
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)


def test_a_fifo_nobody_reads_is_refused_not_waited_on(tmp_path: Path) -> None:
    fifo = tmp_path / "out.toml"
    os.mkfifo(fifo)
    proc = _run(["init", "--force", str(fifo)], tmp_path)  # the timeout of _run is the hang guard
    _one_line_error(proc, str(fifo), "FIFO")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_fifo_with_a_reader_gets_the_file(tmp_path: Path) -> None:
    fifo = tmp_path / "out.toml"
    os.mkfifo(fifo)
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # a reader holds it open
    try:
        proc = _run(["init", "--force", str(fifo)], tmp_path)
        assert proc.returncode == 0, proc.stderr
        chunks = []
        while True:
            try:
                chunk = os.read(fd, 65536)
            except BlockingIOError:
                break
            if not chunk:
                break
            chunks.append(chunk)
    finally:
        os.close(fd)
    text = b"".join(chunks).decode("utf-8")
    assert "[capsule]" in text, "the design went through the pipe"
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_socket_is_refused_before_any_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "s.toml"
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        sock.bind(str(path))
        proc = _here(["optimize", "-o", str(path)], tmp_path, monkeypatch)
    finally:
        sock.close()
    _one_line_error(proc, "-o", "socket")
    assert stat.S_ISSOCK(os.lstat(path).st_mode)


@pytest.mark.parametrize(
    ("args", "first"),
    [
        (["fit", CSV, "-o", "T.toml", "--plot", "P.png"], "T.toml"),
        (
            [*WAVEFORMS, "--csv", "C.csv", "--plot", "P.png"],
            "C.csv",
        ),
    ],
)
def test_two_outputs_are_written_both_or_neither(
    tmp_path: Path, args: list[str], first: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    try:  # a copy of /dev/full: the plot fails on a full disk (a link to it would be refused)
        os.mknod(tmp_path / "P.png", stat.S_IFCHR | 0o666, os.stat("/dev/full").st_rdev)
    except PermissionError:
        pytest.skip("creating a device node needs root")
    proc = _here(args, tmp_path, monkeypatch)
    _one_line_error(proc, "P.png", "No space left")
    assert not (tmp_path / first).exists(), f"{first} is not left behind when the plot fails"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P.png"], "no temporary file left"
    (tmp_path / "P.png").unlink()
    ok = _here(args, tmp_path, monkeypatch)
    assert ok.returncode == 0, ok.stderr
    assert (tmp_path / first).stat().st_size > 0 and (tmp_path / "P.png").stat().st_size > 0


#: ``torque`` at 120 frequencies: 9.6 kB of text, 15 kB of JSON, each more than one 4096-byte
#: block of /dev/full (as ``coils``' 5.2 and 13.8 kB were), so the write fails while printing,
#: not only at the last flush; a process that imports no optimiser (0.2 s of CPU, not 0.8)
TORQUE_TABLE = ["torque", "--frequency", *(f"{0.1 * i:.1f}" for i in range(1, 121))]


@pytest.mark.parametrize("json_flag", [[], ["--json"]])
def test_stdout_on_a_full_disk_is_an_error(tmp_path: Path, json_flag: list[str]) -> None:
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    with open("/dev/full", "w") as full:
        proc = subprocess.run(
            [*SPIRALCAP, *TORQUE_TABLE, *json_flag],
            cwd=tmp_path,
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            timeout=300,
        )
    _one_line_error(proc, "cannot write the output", "No space left")
