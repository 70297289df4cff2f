"""Choosing a structure model: ``auto`` takes the cheapest measured model within the accuracy."""
import pytest

import fsi.setup.models as models


@pytest.fixture
def table(monkeypatch):
    fake = {"thesis": {20: (1.0, 12.0, True), 38: (5.0, 11.0, True)},
            "xpbd": {20: (0.5, 20.0, True), 38: (2.0, 8.0, True), 54: (4.0, 1.0, False)},
            "shell": {20: (9.0, 4.0, True), 38: (30.0, 2.0, True)}}
    monkeypatch.setattr(models, "MODEL_TABLE", fake)
    return fake


def test_auto_picks_the_cheapest_model_meeting_the_accuracy(table):
    assert models.choose_model("auto", 20, 25.0) == "xpbd"
    assert models.choose_model("auto", 20, 15.0) == "thesis"
    assert models.choose_model("auto", 20, 5.0) == "shell"
    assert models.choose_model("auto", 38, 10.0) == "xpbd"
    assert models.choose_model("auto", 26, 15.0) == "thesis"  # nearest measured grid: 20
    assert models.choose_model("auto", 54, 3.0) == "shell"  # xpbd did not converge at 54


def test_auto_falls_back_to_the_most_accurate_model(table, caplog):
    assert models.choose_model("auto", 20, 1.0) == "shell"
    assert "no structure model meets" in caplog.text


def test_explicit_model_is_kept_and_unknown_is_refused(table):
    assert models.choose_model("thesis", 20, 1.0) == "thesis"
    with pytest.raises(ValueError, match="unknown structure model"):
        models.choose_model("ansys", 20, 1.0)


def test_auto_uses_unconverged_measurements_only_when_nothing_converged(monkeypatch, caplog):
    monkeypatch.setattr(models, "MODEL_TABLE", {"thesis": {38: (5.0, 9.0, False)},
                                                "shell": {38: (30.0, 1.8, False)}})
    assert models.choose_model("auto", 38, 5.0) == "shell"
    assert "unconverged" in caplog.text
    monkeypatch.setattr(models, "MODEL_TABLE", {})
    assert models.choose_model("auto", 26, 5.0) == "thesis"
