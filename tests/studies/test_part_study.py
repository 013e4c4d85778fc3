import pytest

from flexarm.fe import MATERIALS
from flexarm.studies.part_study import bar_link, study_part

STEEL = MATERIALS["steel"]


def test_study_errors_fall_with_modes_and_compliance_exact():
    meshes = [("bar", *bar_link(divisions=(10, 2, 2)))]
    rows = study_part(STEEL, meshes, ("rbe2", "rbe3", "k4"), (5, 10, 20, 40))
    for rep in ("rbe2", "rbe3", "k4"):
        errs = [r.freq_error for r in rows if r.representation == rep]
        assert all(a >= b for a, b in zip(errs, errs[1:], strict=False)), rep
        assert errs[-1] < 1e-3
    assert max(r.compliance_error for r in rows) < 1e-8
    with pytest.raises(ValueError, match="representation must be among"):
        study_part(STEEL, meshes, ("k5",))
