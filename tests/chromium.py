"""Headless Chromium for the report's browser tests: find it, and lay a page out at a window
width with the DOM (after the page's scripts ran) on stdout."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path


def chromium() -> str | None:
    """The Chromium (or Chrome) on PATH, or None (the browser tests then skip)."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def dump_dom(
    browser: str, page: Path, window_px: int, profile: Path
) -> subprocess.CompletedProcess:
    """Load ``page`` headless in a ``window_px`` x 1600 window; the laid-out DOM on stdout."""
    cmd = [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        f"--user-data-dir={profile}",
        f"--window-size={window_px},1600",
        "--dump-dom",
        page.resolve().as_uri(),
    ]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=180, check=False)
