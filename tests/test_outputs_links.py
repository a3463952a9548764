"""Outputs that cannot be turned against their user: links refused, no folder made, modes kept.

Every output path goes through :mod:`spiralcap.outputs`: a symbolic link is refused (exit 2, one
line naming it; the file it points at keeps its bytes and mode), a missing parent folder is
refused (nothing created), a replaced file keeps its permission bits and owner, a new file gets
the umask's mode, and devices and FIFOs are written into. The hypothesis test draws the path
situations (links, dangling links, links to folders, missing folders, devices, existing files
with modes, umasks) and checks both the early check and the writer against a snapshot of the
folder.
"""

from __future__ import annotations

import os
import stat
import subprocess
import tempfile
from pathlib import Path

import pytest
from cli_outcome import run
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from proc_util import SPIRALCAP

from spiralcap.core.errors import DataError, InputError
from spiralcap.outputs import check_output, write_files_atomic, write_text_atomic

ROOT = Path(__file__).resolve().parents[1]
CSV = str(ROOT / "examples" / "bench_synthetic_sample2.csv")
SECRET = b"root's own file\n"


def _snapshot(folder: Path) -> dict[str, tuple]:
    """Every entry under ``folder``: kind, permission bits, owner, and bytes or link target."""
    out: dict[str, tuple] = {}
    for dirpath, dirnames, filenames in os.walk(folder):
        for name in dirnames + filenames:
            p = Path(dirpath) / name
            st_ = os.lstat(p)
            if stat.S_ISLNK(st_.st_mode):
                body: object = ("link", os.readlink(p))
            elif stat.S_ISREG(st_.st_mode):
                body = ("file", p.read_bytes())
            else:
                body = ("other", stat.S_IFMT(st_.st_mode))
            key = str(p.relative_to(folder))
            out[key] = (body, stat.S_IMODE(st_.st_mode), st_.st_uid, st_.st_gid)
    return out


def _one_line_exit_2(rc: int, err: str, *needles: str) -> str:
    lines = err.strip().splitlines()
    assert rc == 2, f"exit 2 expected, got {rc}: {err}"
    assert len(lines) == 1 and "Traceback" not in err, err
    for n in needles:
        assert n in lines[0], f"the message names {n!r}: {lines[0]}"
    return lines[0]


def _private(path: Path) -> Path:
    path.write_bytes(SECRET)
    os.chmod(path, 0o600)
    return path


# --- what the issue must show, through the command -------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["init", "--force", "{link}"],
        ["optimize", "-o", "{link}"],
        ["fit", CSV, "-o", "{link}"],
        ["sweep", "--over", "operation.frequency_hz=0.5:3:4", "--csv", "{link}"],
        ["coils", "--stl", "{link}"],
        ["coils", "--step", "{link}"],
        ["waveforms", "--heading", "1,0,0", "--dwell-s", "1", "--plot", "{link}"],
        ["report", "-o", "{link}"],
    ],
    ids=lambda a: " ".join(a[:2]),
)
def test_a_link_to_a_private_file_is_refused_and_the_file_kept(tmp_path, argv):
    suffix = {"--stl": ".stl", "--step": ".step", "--plot": ".png", "report": ".html"}
    ext = next((v for k, v in suffix.items() if k in argv), ".toml")
    secret = _private(tmp_path / "secret")
    link = tmp_path / f"lnk{ext}"
    link.symlink_to(secret)
    before = _snapshot(tmp_path)
    rc, _, err = run([a.format(link=link) for a in argv])
    _one_line_exit_2(rc, err, str(link), "symbolic link")
    assert _snapshot(tmp_path) == before, "the linked file keeps its bytes and mode 0600"


def test_a_link_planted_in_a_sticky_folder_does_not_redirect_the_output(tmp_path):
    shared = tmp_path / "sticky"
    shared.mkdir()
    os.chmod(shared, 0o1777)  # like /tmp: anyone may plant a name here
    secret = _private(tmp_path / "fit.toml")
    (shared / "fit.toml").symlink_to(secret)
    before = _snapshot(tmp_path)
    rc, _, err = run(["fit", CSV, "-o", str(shared / "fit.toml")])
    _one_line_exit_2(rc, err, "fit.toml", "-o")
    assert _snapshot(tmp_path) == before


def test_a_folder_link_planted_by_another_user_in_a_shared_folder_is_refused(tmp_path):
    """The kernel's protected_symlinks rule, applied whether or not the kernel is set to."""
    if os.geteuid() != 0:
        pytest.skip("giving a link another owner needs root")
    shared, elsewhere = tmp_path / "sticky", tmp_path / "elsewhere"
    shared.mkdir()
    elsewhere.mkdir()
    os.chmod(shared, 0o1777)
    (shared / "proj").symlink_to(elsewhere)
    os.chown(shared / "proj", 4321, 4321, follow_symlinks=False)
    rc, _, err = run(["init", str(shared / "proj" / "x.toml")])
    _one_line_exit_2(rc, err, str(shared / "proj"), "another user")
    assert os.listdir(elsewhere) == []
    os.chown(shared / "proj", 0, 0, follow_symlinks=False)  # a link of one's own is followed
    rc, _, err = run(["init", str(shared / "proj" / "x.toml")])
    assert rc == 0 and os.listdir(elsewhere) == ["x.toml"], err


def test_a_dangling_link_creates_neither_its_folder_nor_its_file(tmp_path):
    link = tmp_path / "out.step"
    link.symlink_to(tmp_path / "made" / "deeper" / "x.step")
    rc, _, err = run(["coils", "--step", str(link)])
    _one_line_exit_2(rc, err, str(link))
    assert sorted(os.listdir(tmp_path)) == ["out.step"], "no folder, no file behind the link"


def test_init_into_a_missing_folder_makes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc, _, err = run(["init", "nope/deeper/x.toml"])
    _one_line_exit_2(rc, err, "nope/deeper/x.toml", "nope does not exist")
    assert os.listdir(tmp_path) == [], "no folder is created"


@pytest.mark.parametrize("mode", [0o600, 0o640, 0o604])
def test_init_force_keeps_the_mode_of_the_file_it_replaces(tmp_path, mode):
    path = tmp_path / "design.toml"
    path.write_text("old")
    os.chmod(path, mode)
    rc, _, err = run(["init", "--force", str(path)])
    assert rc == 0, err
    assert "[capsule" in path.read_text(), "the file was rewritten"
    assert stat.S_IMODE(path.stat().st_mode) == mode, f"mode {mode:o} kept"


def test_a_replaced_file_keeps_its_owner_where_the_process_may(tmp_path):
    if os.geteuid() != 0:
        pytest.skip("giving a file another owner needs root")
    path = tmp_path / "shared.toml"
    path.write_text("old")
    os.chown(path, 4321, 4322)
    os.chmod(path, 0o640)
    write_text_atomic(path, "new")
    st_ = path.stat()
    assert (st_.st_uid, st_.st_gid, stat.S_IMODE(st_.st_mode)) == (4321, 4322, 0o640)


def test_a_system_stream_link_is_written_into(tmp_path):
    """/dev/stdout is a link to the pipe the caller reads: written into, like any FIFO."""
    if not os.path.exists("/dev/stdout"):
        pytest.skip("no /dev/stdout")
    proc = subprocess.run(
        [*SPIRALCAP, "init", "--force", "/dev/stdout"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert "[capsule" in proc.stdout and os.listdir(tmp_path) == []


def test_a_path_turned_into_a_link_after_the_check_is_not_followed(tmp_path):
    """Between the early check and the write the name may change: the writer looks again."""
    secret = _private(tmp_path / "secret")
    out = tmp_path / "out.csv"
    assert check_output("--csv", str(out)) is None
    out.symlink_to(secret)
    with pytest.raises(DataError, match="symbolic link"):
        write_files_atomic({tmp_path / "other.csv": "a", out: "b"})
    assert secret.read_bytes() == SECRET and stat.S_IMODE(secret.stat().st_mode) == 0o600
    assert sorted(os.listdir(tmp_path)) == ["out.csv", "secret"], "all or nothing"


# --- the same situations, drawn ------------------------------------------------------------

SITUATIONS = (
    "new",
    "regular",
    "link to a file",
    "dangling link",
    "link to a folder",
    "missing folder",
    "folder",
    "device",
    "FIFO with a reader",
)


def _make(base: Path, situation: str, mode: int, depth: int) -> tuple[str, object]:
    """Build ``situation`` under ``base``; the output path and what the outcome must be."""
    (base / "elsewhere").mkdir()
    target = base / "elsewhere" / "target.toml"
    target.write_bytes(SECRET)
    os.chmod(target, mode)
    out = base / "out.toml"
    if situation == "regular":
        out.write_bytes(b"old")
        os.chmod(out, mode)
        return str(out), ("kept", mode)
    if situation == "link to a file":
        out.symlink_to(target)
    elif situation == "dangling link":
        out.symlink_to(base / "nowhere" / "x.toml")
    elif situation == "link to a folder":
        out.symlink_to(base / "elsewhere")
    elif situation == "missing folder":
        out = base.joinpath(*[f"m{i}" for i in range(depth)], "out.toml")
    elif situation == "folder":
        out.mkdir()
    elif situation == "device":
        return os.devnull, ("device", None)
    elif situation == "FIFO with a reader":
        os.mkfifo(out)
        return str(out), ("fifo", os.open(out, os.O_RDONLY | os.O_NONBLOCK))
    if situation == "new":
        return str(out), ("new", None)
    return str(out), ("refused", None)


@settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(
    situation=st.sampled_from(SITUATIONS),
    mode=st.sampled_from([0o600, 0o640, 0o644, 0o664, 0o604, 0o400]),
    umask=st.sampled_from([0o022, 0o077, 0o002, 0o027]),
    depth=st.integers(1, 3),
    content=st.binary(max_size=64),
)
def test_output_paths_drawn(situation, mode, umask, depth, content):
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp)
        path, (outcome, extra) = _make(base, situation, mode, depth)
        before = _snapshot(base)
        old_umask = os.umask(umask)
        try:
            _judge(base, path, outcome, extra, content, before, umask)
        finally:
            os.umask(old_umask)
            if outcome == "fifo":
                os.close(extra)


def _judge(base, path, outcome, extra, content, before, umask) -> None:
    if outcome == "refused" or not (outcome != "kept" or os.access(path, os.W_OK)):
        with pytest.raises(InputError) as early:
            check_output("-o", path)
        assert path in str(early.value) and "\n" not in str(early.value)
        if outcome == "kept":
            return  # a read-only file (not root): refused before any work; that is the promise
        with pytest.raises(DataError):
            write_text_atomic(path, content)
        assert _snapshot(base) == before, "nothing written, made or re-moded"
        return
    assert check_output("-o", path) == ({"device": "character device", "fifo": "FIFO"}.get(outcome))
    write_text_atomic(path, content)
    after = _snapshot(base)
    if outcome in ("device", "fifo"):
        assert after == before, "a device or FIFO is written into, nothing made beside it"
        if outcome == "fifo" and content:
            assert os.read(extra, 1 << 16) == content, "the bytes went through the pipe"
        return
    assert Path(path).read_bytes() == content
    expected = extra if outcome == "kept" else 0o666 & ~umask
    assert stat.S_IMODE(os.lstat(path).st_mode) == expected, (outcome, oct(expected))
    rest = {k: v for k, v in after.items() if k != os.path.basename(path)}
    assert rest == {k: v for k, v in before.items() if k != os.path.basename(path)}, (
        "the write touched nothing else (no .part file left)"
    )
