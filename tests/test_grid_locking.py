"""Grid locking (cases/grid_locking.py): the thesis stepper locks a coarse grid
at a tight strain limit and inverts it at a loose one; Courant failures are recorded, not raised;
the locked/inverted classification."""
import numpy as np

from cases import grid_locking as gl
from structure.thesis import CourantError


def test_coarse_grid_locks_at_tight_limit_and_inverts_at_loose():
    # N = 14, short ramp (0.2 s) + hold: measured fill 0.013 at 0.5 %, 0.505 at 5 %.
    tight = gl.run_point(14, 0.5, 0.2, 0.2, 1e-4)
    loose = gl.run_point(14, 5.0, 0.2, 0.2, 1e-4)
    assert tight["status"] == loose["status"] == "ok"
    assert tight["inverted_fraction"] < 0.05
    assert loose["inverted_fraction"] > 0.4
    assert tight["settled"], "the locked membrane must stop moving during the hold"
    assert tight["strain_mean"] < 0.01 < loose["strain_mean"]


def test_courant_error_is_a_failed_point_not_a_crash(monkeypatch):
    calls = {"n": 0}
    real_step = gl.step

    def failing_step(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 20:
            raise CourantError("Courant number 1.5 > 1 at node 0")
        return real_step(*args, **kwargs)

    monkeypatch.setattr(gl, "step", failing_step)
    row = gl.run_point(10, 1.0, 0.01, 0.0, 1e-4)
    assert row["status"] == "courant-error"
    assert "Courant" in row["message"]
    assert np.isfinite(row["inverted_fraction"]) and np.isnan(row["ramp_end_fraction"])


def test_time_step_above_a_priori_courant_limit_is_a_failed_point():
    row = gl.run_point(14, 1.0, 0.5, 0.0, 0.01)
    assert row["status"] == "courant-error" and "Courant" in row["message"]


def test_classify_normalises_by_static_cap_and_keeps_failures():
    caps = {14: 0.6, 38: 0.9}
    rows = [dict(grid_size=38, error_limit=5.0, inverted_fraction=0.81, status="ok"),
            dict(grid_size=38, error_limit=0.5, inverted_fraction=0.50, status="ok"),
            dict(grid_size=14, error_limit=5.0, inverted_fraction=0.50, status="ok"),
            dict(grid_size=14, error_limit=0.5, inverted_fraction=0.10, status="ok",
                 fraction_2x=0.52, status_2x="ok"),
            dict(grid_size=14, error_limit=1.0, inverted_fraction=0.2, status="courant-error")]
    ref = gl.classify(rows, caps)
    assert (ref["grid_size"], ref["error_limit"]) == (38, 5.0)
    assert np.isclose(ref["cap_normalised"], 0.9)
    # threshold 0.8 * 0.9 = 0.72 of each grid's cap
    assert [r["status"] for r in rows] == ["inverted", "locked", "inverted", "locked",
                                           "courant-error"]
    assert rows[3]["status_2x"] == "inverted"
