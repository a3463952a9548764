"""Review fixes of issues 37 and 39: a calibration's survey is an input (never an output of the
same run), a field grid through a winding is refused, a file name in a TOML comment cannot
start a table."""

from __future__ import annotations

import shutil
from pathlib import Path

import tomllib
from cli_outcome import run

ROOT = Path(__file__).resolve().parents[1]
SURVEY = ROOT / "examples" / "field_survey.csv"


def test_a_calibrations_survey_is_never_an_output(tmp_path):
    """cal.toml names its survey (calibration.survey_csv): waveforms --csv onto it exits 2 and
    leaves it byte-identical (issue 39 item 2, a file a design names by reference)."""
    survey = tmp_path / "s.csv"
    shutil.copy(SURVEY, survey)
    cal = tmp_path / "cal.toml"
    rc, _, err = run(["calibrate", str(survey), "-o", str(cal)])
    assert rc == 0, err
    before = survey.read_bytes()
    argv = ["waveforms", str(cal), "--heading", "1,0,0", "--dwell-s", "1", "--csv", str(survey)]
    rc, _, err = run(argv)
    assert rc == 2 and len(err.strip().splitlines()) == 1, (rc, err)
    assert survey.read_bytes() == before, "the survey is untouched"


def test_a_survey_name_cannot_write_toml_into_the_calibration(tmp_path):
    """A newline in the survey's file name stays inside the comment's quoted string: the
    written file parses to the [calibration] table alone (no injected [tissue] table)."""
    survey = tmp_path / "x\n[tissue]\nscale = 3\n#.csv"
    shutil.copy(SURVEY, survey)
    cal = tmp_path / "cal.toml"
    rc, _, err = run(["calibrate", str(survey), "-o", str(cal)])
    if rc == 0:  # accepted: the file holds no table the name spelled
        assert "tissue" not in tomllib.loads(cal.read_text()), cal.read_text()
    else:  # or refused in one line, nothing written
        assert rc == 2 and len(err.strip().splitlines()) == 1 and not cal.exists(), err


def test_a_field_grid_through_a_winding_is_refused(tmp_path):
    """A grid point on the z pair's mean turn (x 280 mm, z 140 mm: radius 280 mm, spacing
    280 mm in the built-in design) has no finite field: exit 2 naming --grid-box-mm, no file,
    where it used to write NaN columns with exit 0."""
    grid = tmp_path / "g.csv"
    rc, _, err = run(["coils", "--field-grid", str(grid), "--grid-box-mm=280,280,0,0,140,140"])
    assert rc == 2 and "--grid-box-mm" in err and "winding" in err, err
    assert not grid.exists()
