"""The documentation's validation figures (``docs/make_validation_figures.py``) are drawn from
``docs/data`` and every one is made: a figure whose JSON field was renamed or removed fails
here, not at the next time someone remakes the figures."""
import importlib.util
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "make_validation_figures.py"


@pytest.fixture(scope="module")
def figures():
    spec = importlib.util.spec_from_file_location("make_validation_figures", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_validation_figure_is_drawn_from_the_data(figures, tmp_path, monkeypatch):
    monkeypatch.setattr(figures, "FIGURES_DIR", tmp_path)
    written = figures.main([])
    assert sorted(p.name for p in written) == sorted(f"validation_{n}.png" for n in figures.FIGURES)
    for path in written:
        assert path.stat().st_size > 20_000, path.name       # a drawn figure, not a blank one
    with pytest.raises(SystemExit, match="unknown figure"):
        figures.main(["no-such-figure"])
