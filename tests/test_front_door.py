"""One front door per stage (issue 23): the API and the CLI give the same results, and
failures and inputs are handled below the API once."""

from __future__ import annotations

import pytest

from springcad.errors import CheckFailed


def test_failed_verdicts_are_one_family():
    from fea.verdict import VerificationFailed
    from springcad.geometry.checks import CheckReport, ChecksFailed

    assert issubclass(VerificationFailed, CheckFailed)
    assert issubclass(ChecksFailed, CheckFailed)
    # a report with a failed error check raises the family's class, not a translation
    from springcad.geometry.checks import Check

    bad = CheckReport([Check("solid_valid", "S1-RING", False, message="not a valid solid")])
    with pytest.raises(CheckFailed, match="S1-RING: solid_valid: not a valid solid"):
        bad.raise_if_failed()
