"""``examples/gallery.py`` writes every report figure from the Python API."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_gallery_writes_every_report_figure(tmp_path: Path) -> None:
    spec = importlib.util.spec_from_file_location("gallery", ROOT / "examples" / "gallery.py")
    assert spec and spec.loader
    gallery = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gallery)
    written = gallery.main(
        str(tmp_path),
        power_factors=(0.5, 2.0),
        refinements=1,
        fmt="png",
        uncertainty_samples=1024,
    )
    names = {p.stem for p in written}
    # the report's figure ids, read from the report's source (every "fig-..." it declares),
    # without the "fig-" prefix: a figure added to the report must be added to the gallery
    import re

    sections = ROOT / "spiralcap" / "report" / "sections"
    report_ids = {
        m
        for f in sections.glob("*.py")
        for m in re.findall(r'"fig-([a-z0-9-]+)"', f.read_text(encoding="utf-8"))
    }
    assert len(report_ids) >= 12, report_ids
    assert report_ids <= names, f"every report figure drawn from Python: {report_ids - names}"
    for p in written:
        assert p.read_bytes().startswith(b"\x89PNG"), f"{p.name} is an image"
        assert p.stat().st_size > 5000, f"{p.name} is not blank"


def test_api_names_do_not_collide_with_figure_modules() -> None:
    """``spiralcap.figures.<name>`` must stay the function after any submodule is imported."""
    import pkgutil

    import spiralcap.figures as figures
    from spiralcap.figures import api

    modules = {m.name for m in pkgutil.iter_modules(figures.__path__)}
    assert modules.isdisjoint(figures._API), "an API function shadowed by a submodule"
    for name in figures._API:
        assert getattr(figures, name) is getattr(api, name)
