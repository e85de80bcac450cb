from __future__ import annotations

import pytest

from geomcheck.errors import UsageError
from geomcheck.thresholds import Thresholds


def test_override_converts_and_keeps_other_fields() -> None:
    t = Thresholds().with_overrides({"fit": {"protrusion_tolerance_m": 0.02, "surface_samples": 500.0}})
    assert t.fit.protrusion_tolerance_m == 0.02
    assert t.fit.surface_samples == 500
    assert isinstance(t.fit.surface_samples, int)
    assert t.fit.min_coverage == Thresholds().fit.min_coverage
    assert t.inertia == Thresholds().inertia


def test_unknown_family_names_the_choices() -> None:
    with pytest.raises(UsageError, match=r"invalid threshold family 'fitt'.*fit"):
        Thresholds().with_overrides({"fitt": {}})


def test_unknown_field_names_the_choices() -> None:
    with pytest.raises(UsageError, match=r"invalid threshold in fit 'coverage'.*min_coverage"):
        Thresholds().with_overrides({"fit": {"coverage": 0.5}})


@pytest.mark.parametrize("value", ["0.5", True])
def test_non_number_is_refused(value: object) -> None:
    with pytest.raises(UsageError, match="must be a number"):
        Thresholds().with_overrides({"fit": {"min_coverage": value}})


def test_integer_field_refuses_fraction() -> None:
    with pytest.raises(UsageError, match="must be an integer"):
        Thresholds().with_overrides({"fit": {"surface_samples": 10.5}})
