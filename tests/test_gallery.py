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
    written = gallery.main(str(tmp_path), power_factors=(0.5, 2.0), refinements=1, fmt="png")
    names = {p.stem for p in written}
    # the report's figure ids, without the "fig-" prefix
    report_ids = {
        "geometry",
        "field-maps",
        "field-profiles",
        "tissue-torque",
        "margin-frequency",
        "margin-map",
        "torque-budget",
        "utilisation",
        "margin-angle",
        "margin-power",
    }
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
