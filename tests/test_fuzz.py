"""Property-based fuzzing (Hypothesis) of what a user hands fsi: scene TOML and .obj text.
Whatever the text, fsi answers with a result or one line naming the file, key or line and
exit status 2; no traceback escapes and nothing is written for a refused input."""
import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from fsi import registry
from fsi.cli import main
from fsi.scene import SCHEMA
from tests.test_runs import RAMP

KEYS = [(section, name) for section, table in SCHEMA.items() for name in table]
VALUES = st.one_of(
    st.integers(min_value=-10**12, max_value=10**12).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda v: repr(v).replace("inf", "inf")),
    st.sampled_from(["true", "false", '"clamped"', '"xpbd"', '"tank"', '"auto"', "[]",
                     "[0.0, 0.0, 0.0]", "[1, 2]", '"\\u00e9"', "0", "1e309", "-0.0", "nan",
                     "[0.1, 0.5, 0.9]", "{a = 1}", '"thesis-ramp"', '"coupled-fill"',
                     '"volume-sweep"', '"slosh"', '"plate-estimate"']),
    st.text(max_size=12).map(lambda t: '"' + t.replace("\\", "").replace('"', "") + '"'))
LINES = st.one_of(
    st.tuples(st.sampled_from(KEYS), VALUES).map(lambda kv: (kv[0][0], f"{kv[0][1]} = {kv[1]}")),
    st.tuples(st.sampled_from(list(SCHEMA) + ["bogus"]),
              st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=30)))


class Computed(Exception):
    """A scene that validated reached its procedure: the fuzz stops it there."""


@pytest.fixture(scope="module")
def small_result(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz")
    (d / "small.toml").write_text(RAMP)
    assert main(["run", str(d / "small.toml"), "--out", str(d / "run"), "--no-plots"]) == 0
    return d / "run"


def _scene_text(lines) -> str:
    tables: dict = {}
    for section, line in lines:
        tables.setdefault(section, []).append(line)
    return "".join(f"[{s}]\n" + "\n".join(body) + "\n" for s, body in tables.items())


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines=st.lists(LINES, max_size=6), raw=st.binary(max_size=20), use_raw=st.booleans())
@example(lines=[("membrane", "grid_size = 4")], raw=b"", use_raw=False)  # no free node
def test_any_scene_text_runs_or_is_refused_in_one_line(tmp_path, capsys, monkeypatch, lines,
                                                       raw, use_raw):
    def stop(self, setup, progress):
        raise Computed
    monkeypatch.setattr(registry.Procedure, "__call__", stop)
    capsys.readouterr()  # what earlier examples printed
    scene = tmp_path / "fuzz.toml"
    if use_raw:
        scene.write_bytes(raw)
    else:
        scene.write_text(_scene_text(lines), encoding="utf-8")
    out = tmp_path / "out"
    try:
        status = main(["run", str(scene), "--out", str(out)])
    except Computed:
        return  # a valid scene: fine
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and err[0].startswith("fsi: error: ")
    assert not out.exists()


OBJ_LINES = st.one_of(
    st.tuples(st.just("v"), st.lists(st.one_of(st.floats(-1.0, 1.0), st.floats(),
                                               st.text(max_size=3)), max_size=4)),
    st.tuples(st.just("f"), st.lists(st.one_of(st.integers(-5, 40), st.text(max_size=3)),
                                     max_size=5)),
    st.tuples(st.sampled_from(["vn", "vt", "#", "o", "g", "s", "usemtl", ""]),
              st.lists(st.text(max_size=5), max_size=3)))


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines=st.lists(OBJ_LINES, max_size=30))
def test_any_obj_text_compares_or_is_refused_in_one_line(small_result, tmp_path, capsys, lines):
    obj = tmp_path / "scan.obj"
    obj.write_text("\n".join(f"{k} {' '.join(map(str, v))}" for k, v in lines) + "\n")
    capsys.readouterr()
    status = main(["compare", str(small_result), str(obj)])
    captured = capsys.readouterr()
    if status == 0:
        assert captured.out.startswith("tank A")
        return
    err = captured.err.strip().splitlines()
    assert status == 2 and len(err) == 1 and err[0].startswith("fsi: error: ")


def test_a_surface_that_fits_the_tank_is_compared(small_result, tmp_path, capsys):
    """The fuzz's positive case by construction: a disc of radius R at z = -R/2."""
    radius = 0.20955
    angle = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    ring = np.stack([radius * np.cos(angle), radius * np.sin(angle), -0.5 * radius + 0 * angle],
                    1)
    points = np.vstack([[0.0, 0.0, -0.5 * radius], ring])
    faces = [(1, 2 + k, 2 + (k + 1) % 12) for k in range(12)]
    obj = tmp_path / "disc.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in points)
                   + "".join(f"f {a} {b} {c}\n" for a, b, c in faces))
    assert main(["compare", str(small_result), str(obj)]) == 0
