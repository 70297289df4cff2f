"""README stays true: its scene reference table is the one the schema generates."""
from pathlib import Path

from fsi.scene import reference_markdown


def test_readme_scene_reference_matches_schema():
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    assert reference_markdown() in readme
