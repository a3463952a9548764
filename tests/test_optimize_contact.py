"""Issue 22: `optimize` on designs whose optimum sits where the spiral stops touching the wall.

A lumen just wider than the capsule (11.4-11.5 mm, the sample-2 tissue alone) put the optimum on
the corner of ``max(strain, 0)`` (IPOPT cycled there, "infeasible ... solver"); a design that
needs no torque at all divided 0 by 0 in the safety-factor row (16 "NaN detected" lines from
CasADi on file descriptor 2). Run as a subprocess: in-process runs cannot see what CasADi writes.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import bad_numbers

ROOT = Path(__file__).resolve().parents[1]
ALONE = ["--set", "tissue.worst_case_presets=[]"]
#: No tolerance box: these cases are about the contact's kink at the nominal design (a lumen a
#: hair's breadth narrower than D' leaves no room for one; tests/test_tolerances.py has the box).
NO_TOLERANCES = [
    "tolerances.helical_angle_deg=0",
    "tolerances.spiral_wire_diameter_mm=0",
    "tolerances.lumen_diameter_mm=0",
]


#: The script of the one subprocess that runs every case (a fresh interpreter: CasADi writes
#: on file descriptors 1 and 2, which in-process runs cannot see). Each case gets its own files
#: on descriptors 1 and 2 while it runs (its stdout and stderr, as a process of its own would
#: have them) and its exit status (a traceback, as Python prints it, and 1 if it raises).
_SCRIPT = """
import json, os, sys, tempfile, traceback
from dataclasses import replace


def no_torque(sets):
    from optimize import optimize_design, prepare
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.serialize import optimization_to_dict

    m = build_model(load_design(None, sets))
    m = prepare(replace(m, capsule=replace(m.capsule, set_mass_kg=0.0)))
    print(json.dumps(optimization_to_dict(optimize_design(m))))
    return 0


def cli(argv):
    from spiralcap.cli import main

    return main(argv)


results = {}
for name, kind, args in json.loads(sys.argv[1]):
    files = [tempfile.TemporaryFile(mode="w+b") for _ in range(2)]
    saved = [os.dup(1), os.dup(2)]
    sys.stdout.flush(); sys.stderr.flush()
    os.dup2(files[0].fileno(), 1); os.dup2(files[1].fileno(), 2)
    try:
        rc = (cli if kind == "cli" else no_torque)(args)
    except SystemExit as exc:
        rc = exc.code if isinstance(exc.code, int) else 1
    except BaseException:
        traceback.print_exc()
        rc = 1
    sys.stdout.flush(); sys.stderr.flush()
    os.dup2(saved[0], 1); os.dup2(saved[1], 2)
    out, err = (f.seek(0) or f.read().decode() for f in files)
    results[name] = [rc, out, err]
print(json.dumps(results))
"""


@pytest.fixture(scope="module")
def outcomes() -> dict[str, tuple[int, dict, str]]:
    """Every case of this module in one fresh interpreter (one start-up and import instead of
    four): case name -> (exit status, stdout as JSON, stderr)."""
    cases = [
        (f"lumen {lumen_mm}", "cli", ["optimize", "--json", *_lumen_sets(lumen_mm)])
        for lumen_mm in LUMENS_MM
    ]
    cases.append(("no torque", "no_torque", NO_TORQUE_SETS))
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    run = subprocess.run(
        [sys.executable, "-c", _SCRIPT, json.dumps(cases)],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=600,
    )
    assert run.returncode == 0 and run.stderr.strip() == "", run.stderr
    found = json.loads(run.stdout)
    return {
        name: (rc, json.loads(out) if out.strip() else {}, err)
        for name, (rc, out, err) in found.items()
    }


LUMENS_MM = (11.4, 11.45, 11.5)


def _lumen_sets(lumen_mm: float) -> tuple[str, ...]:
    return (
        *ALONE,
        "--set",
        f"tissue.lumen_diameter_mm={lumen_mm}",
        *(a for v in NO_TOLERANCES for a in ("--set", v)),
    )


#: A weightless capsule in a 12 mm lumen pushing no load (test_a_design_needing_no_torque_...).
NO_TORQUE_SETS = [
    "tissue.worst_case_presets=[]",
    "tissue.lumen_diameter_mm=12",
    "requirements.axial_load_mN=0",
    "requirements.min_speed_mm_s=2",  # the grip holds the angle near 2.4 deg: a slow screw
    *NO_TOLERANCES,
]


def _grid_best_margin_Nm(*sets: str) -> float:
    """The best feasible margin on a dense angle x frequency grid (an independent search)."""
    from optimize.evaluate import margin_grid
    from optimize.system import prepare
    from spiralcap.design import load_design
    from spiralcap.robust import optimization_model

    pairs = [s for s in sets if s != "--set"]
    model = prepare(optimization_model(load_design(None, pairs)))
    b = model.bounds
    a = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 400)
    f = np.geomspace(b.frequency_min_hz, b.frequency_max_hz, 200)
    g = margin_grid(model, a[:, None], f[None, :], capacity=True)
    return float(np.max(np.where(g.feasible, g.margin_Nm, -np.inf)))


@pytest.mark.parametrize("lumen_mm", LUMENS_MM)
def test_a_lumen_just_wider_than_the_capsule_is_optimised(outcomes, lumen_mm):
    sets = _lumen_sets(lumen_mm)
    rc, out, err = outcomes[f"lumen {lumen_mm}"]
    assert rc == 0, f"exit 0 (issue 22: was exit 3 'meets solver'); stderr {err!r}"
    assert "NaN" not in err and err.strip() == "", f"nothing on stderr: {err!r}"
    assert not bad_numbers(out), bad_numbers(out)
    grid = _grid_best_margin_Nm(*sets)
    assert out["margin_Nm"] >= grid * (1 - 1e-6), (
        f"the optimum ({out['margin_Nm']:.6e} N·m) is at least the best of a 400 x 200 grid "
        f"({grid:.6e} N·m) within 1e-6"
    )


def test_a_design_needing_no_torque_is_optimised_without_nan(outcomes):
    """A weightless capsule in a 12 mm lumen pushing no load: nothing resists wherever the
    spiral is off the wall. No design file reaches that (capsule.mass_g >= 0.1 g), so the model
    is built in Python, in the subprocess that shows what CasADi writes on file descriptor 2."""
    rc, out, err = outcomes["no torque"]
    assert rc == 0, err
    assert "NaN" not in err and err.strip() == "", f"stderr: {err!r}"
    assert not bad_numbers(out), bad_numbers(out)
    assert out["status"] == "optimal"
    assert min(out["evaluation"]["wall_strains"]) >= 0.0168 * (1 - 1e-6), "it grips (1.68 %)"
