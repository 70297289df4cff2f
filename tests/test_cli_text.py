"""What the command line prints: help in plain whole sentences, aligned tables, listings that
fit the terminal, a suggestion for a mistyped name, a note before a slow advice, and log
lines that never share a line with the progress bar."""
import argparse
import io
import logging
import re
import sys
import warnings

import pytest

from fsi.cli import build_parser, main
from fsi.run_job import ProgressBar, progress_shown
from fsi.scene import SceneError, bundled_scenes, load_scene, parse_scene
from fsi.sweep.file import SweepError, bundled_sweep_text, bundled_sweeps, parse_sweep
from fsi.text import about, format_table, suggestion

COMMANDS = ("run", "sweep", "compare", "advise", "show", "scenes", "sweeps")


def column_spans(lines: list[str]) -> list[tuple[int, int]]:
    """(start, end) of each column of a table: the runs of character positions that are not
    blank on every line, columns being two or more blank positions apart on every line."""
    width = max(map(len, lines))
    used = [any(i < len(line) and line[i] != " " for line in lines) for i in range(width)]
    spans, start, blank = [], None, 0
    for i, u in enumerate(used + [False, False]):
        if u:
            start, blank = (i if start is None else start), 0
            continue
        blank += 1
        if start is not None and blank == 2:
            spans.append((start, i - 1))
            start = None
    return spans


# ------------------------------------------------------------------ help

def subcommand_parsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {"fsi": parser, **action.choices}


@pytest.mark.parametrize("command", [(), *((c,) for c in COMMANDS)])
def test_help_is_plain_text_that_fits_80_columns(command, capsys, monkeypatch):
    """No reStructuredText (double backquotes, roles) in any help, and every line fits an
    80-column terminal (its lists kept as written)."""
    monkeypatch.setenv("COLUMNS", "80")
    with pytest.raises(SystemExit) as stop:
        main([*command, "--help"])
    assert stop.value.code == 0
    text = capsys.readouterr().out
    assert "``" not in text and not re.search(r":(func|data|mod|class):", text)
    assert [line for line in text.splitlines() if len(line) > 80] == []


def test_every_description_is_whole_sentences():
    for name, parser in subcommand_parsers().items():
        description = parser.description.strip()
        assert description[0].isupper() and description.endswith("."), name
    assert set(subcommand_parsers()) == {"fsi", *COMMANDS}


def test_the_help_lists_the_commands_and_the_exit_statuses(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    text = capsys.readouterr().out
    assert all(f"  fsi {command} " in text for command in COMMANDS)
    for status in ("0 ", "1 ", "2 ", "3 ", "130/143 "):
        assert re.search(rf"^  {status}", text, flags=re.M), status


# ------------------------------------------------------------------ tables

def test_format_table_lines_its_columns_up():
    rows = [(0.25, 713.9, "small", 4004.76, None), (0.5, 2055.7, "hencky", 37.93, "*"),
            (0.125, 5.0, "large", 1.0, None)]
    text = format_table([("tank fraction", "-"), ("load", "Pa"), ("estimate", ""),
                         ("w0", "mm"), ("", "")], rows, [".3f", ".1f", "", ".2f", ""])
    lines = text.split("\n")
    assert re.split(" {2,}", lines[0]) == ["tank fraction (-)", "load (Pa)", "estimate",
                                           "w0 (mm)"]
    spans = column_spans(lines)
    assert len(spans) == 5
    for line in lines[1:]:  # numbers end, text starts, where the column does
        assert line[spans[1][1] - 1] != " " and line[spans[2][0]] != " "
    assert all(line == line.rstrip() for line in lines)
    with pytest.raises(ValueError, match="need 5 values"):
        format_table(None, [(1, 2)], ["", "", "", "", ""])


def test_a_listing_wraps_its_last_column_with_a_hanging_indent():
    text = format_table(None, [("a", "one two three four five six seven eight nine ten"),
                               ("a-long-name", "short")], ["", ""], width=40)
    assert text.split("\n") == ["a            one two three four five six",
                                "             seven eight nine ten",
                                "a-long-name  short"]


def test_the_plate_report_is_a_table_with_units(tmp_path, capsys):
    """fsi run thesis-plate: a row per fill and estimate, every column at the same place on
    every line, each header naming its unit."""
    assert main(["run", "thesis-plate", "--out", str(tmp_path / "p"), "--no-plots"]) == 0
    out = capsys.readouterr().out.splitlines()
    start = next(i for i, line in enumerate(out) if line.startswith("tank fraction"))
    table = out[start:start + 7]
    assert re.split(" {2,}", table[0]) == ["tank fraction (-)", "load (Pa)", "estimate",
                                           "w0 (mm)", "w0/t (-)", "valid w0/t", "in range"]
    spans = column_spans(table)
    assert len(spans) == 7
    for line in table[1:]:
        for number in (3, 4):  # w0 and w0/t end where their column does
            assert line[spans[number][1] - 1] != " " and \
                line[spans[number][1]:spans[number][1] + 1] in ("", " ")
    assert [line[spans[2][0]:spans[2][1]].strip() for line in table[1:]] == \
        ["small", "large", "hencky"] * 2


def test_a_compare_table_names_its_columns_and_units(tmp_path, capsys):
    """fsi compare of a result with itself: tank fractions and a zero error, in columns."""
    out = tmp_path / "p"
    scene = tmp_path / "tiny.toml"
    scene.write_text("[scene]\nname = 'tiny'\nprocedure = 'volume-sweep'\n[membrane]\n"
                     "grid_size = 8\n[structure]\nmodel = 'xpbd'\n[sweep]\nscale = 'tank'\n"
                     "fills = [0.1, 0.2]\ndrain = false\n")
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) in (0, 3)
    capsys.readouterr()
    assert main(["compare", str(out), str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert re.split(" {2,}", lines[0]) == ["tank A (-)", "tank B (-)", "Eqn 6.1 error (%)"]
    assert len(column_spans(lines)) == 3 and len(lines) == 3
    assert [float(line.split()[2]) for line in lines[1:]] == [0.0, 0.0]


# ------------------------------------------------------------------ listings

@pytest.mark.parametrize("command, names, description", [
    ("scenes", bundled_scenes, lambda name: load_scene(name)["scene"]["description"]),
    ("sweeps", bundled_sweeps, None)])
def test_a_listing_pads_to_the_longest_name_and_wraps_to_the_terminal(command, names,
                                                                      description, capsys,
                                                                      monkeypatch):
    monkeypatch.setenv("COLUMNS", "60")
    assert main([command]) == 0
    lines = capsys.readouterr().out.splitlines()
    indent = max(map(len, names())) + 2
    entries = [i for i, line in enumerate(lines) if not line.startswith(" ")]
    assert [lines[i].split()[0] for i in entries] == names()
    assert all(lines[i][indent - 2:indent] == "  " and lines[i][indent] != " "
               for i in entries)
    assert all(line[:indent].strip() == "" and line[indent] != " "
               for i, line in enumerate(lines) if i not in entries)
    assert all(len(line) <= 60 for line in lines)
    if description is not None:  # the descriptions whole, only wrapped
        texts = " ".join(line[indent:] if i not in entries else "\n" + line[indent:]
                         for i, line in enumerate(lines)).split("\n")[1:]
        assert [" ".join(t.split()) for t in texts] == [description(n) for n in names()]


# ------------------------------------------------------------------ did you mean

def test_an_unknown_scene_gets_the_closest_name(tmp_path, capsys):
    assert main(["run", "thesis-statc", "--out", str(tmp_path / "r")]) == 2
    assert capsys.readouterr().err == ("fsi: error: unknown scene 'thesis-statc'; did you mean "
                                       "'thesis-static'? (fsi scenes lists them)\n")
    assert main(["scenes", "no-such-thing"]) == 2
    assert capsys.readouterr().err == ("fsi: error: unknown scene 'no-such-thing': not a file, "
                                       "and not a bundled scene (fsi scenes lists them)\n")


def test_an_unknown_sweep_gets_the_closest_name(capsys):
    assert main(["sweeps", "slosh-by-fil"]) == 2
    assert capsys.readouterr().err == ("fsi: error: unknown sweep 'slosh-by-fil'; did you mean "
                                       "'slosh-by-fill'? (fsi sweeps lists them)\n")


@pytest.mark.parametrize("text, message", [
    ("[membrane]\nthicknes = 0.001", "unknown scene key 'membrane.thicknes'; did you mean "
                                     "'membrane.thickness'? allowed in [membrane]: grid_size,"),
    ("[membrane]\ncells = 16", "unknown scene key 'membrane.cells'; did you mean 'fluid.cells'?"),
    ("[membrane]\ncolour = 'red'", "unknown scene key 'membrane.colour'; allowed in [membrane]"),
    ("[membrne]\nthickness = 0.001", "unknown scene section '[membrne]'; did you mean "
                                     "'[membrane]'? allowed: scene,"),
    ("grid_size = 8", "unknown scene section '[grid_size]'; did you mean "
                      "'membrane.grid_size', under [membrane]?"),
])
def test_an_unknown_scene_key_gets_the_closest_key(text, message):
    with pytest.raises(SceneError) as err:
        parse_scene(text)
    assert str(err.value).startswith(message)


def test_a_mistyped_scene_key_is_one_line_and_exit_2(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text("[scene]\nprocedure = 'plate-estimate'\n[plate]\nfill = [0.25]\n")
    assert main(["run", str(scene), "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did you mean 'plate.fills'?" in err


@pytest.mark.parametrize("text, message", [
    ("[sweep]\nscene = 'x'\n[vari]\na = [1]", "s.toml: unknown table [vari]; did you mean "
                                              "[vary]? allowed: sweep, set, vary, zip"),
    ("[sweep]\nscene = 'x'\nnmae = 'y'", "s.toml: unknown key 'sweep.nmae'; did you mean "
                                         "'sweep.name'? allowed: name,"),
])
def test_an_unknown_sweep_key_gets_the_closest_key(text, message):
    with pytest.raises(SweepError) as err:
        parse_sweep(text, "s.toml")
    assert str(err.value).startswith(message)


def test_suggestion_is_empty_when_nothing_is_close():
    assert suggestion("thesis-fil", bundled_scenes()) == "did you mean 'thesis-fill'?"
    assert suggestion("zzz", bundled_scenes()) == ""
    assert bundled_sweep_text(bundled_sweeps()[0])


# ------------------------------------------------------------------ advise

def test_advise_says_what_it_computes_before_it_computes(capsys, monkeypatch):
    """The slosh periods of a fill take seconds (20 s more while the fluid kernels compile)
    and the onset of folding about 10 s: one line on stderr says each before it is computed;
    a fixed answer with nothing to compute (the plate) says nothing."""
    from fsi.analysis import onset, regime

    said = []

    def cheap(scene):  # the regime's numbers, without the eigenvalue problems
        said.append(capsys.readouterr().err)
        return regime.Regime(dynamic_pressure=1.0, hydrostatic_pressure=2000.0,
                             fill_time=100.0, slosh_period=1.0, period_fills=(0.1, 0.9),
                             periods=(1.0, 0.9))

    def no_onset(scene):  # the onset's lines, without the shell of revolution
        said.append(capsys.readouterr().err)
        return ["the onset"]
    monkeypatch.setattr(regime, "regime", cheap)
    monkeypatch.setattr(onset, "onset_lines", no_onset)
    assert main(["advise", "thesis-fill"]) == 0
    assert len(said) == 2 and said[0].count("\n") == 1 and said[1].count("\n") == 1
    assert said[0].startswith("thesis-fill: computing the liquid's first slosh period at tank "
                              "fractions 0.1 and 0.9 on its 16-cell fluid grid (under a second")
    assert said[1].startswith("thesis-fill: computing where its diaphragm starts to fold (the "
                              "shell of revolution, 128 meridian elements, about 10 s)")
    out = capsys.readouterr().out
    assert out.startswith("thesis-fill: static model") and "  the onset" in out
    assert main(["advise", "thesis-static"]) == 0
    assert said[-1].startswith("thesis-static: computing where its diaphragm starts to fold")
    assert main(["advise", "thesis-plate"]) == 0
    assert capsys.readouterr().err == ""


def test_about_rounds_a_duration():
    assert [about(s) for s in (0.3, 1.23, 20.4, 89.0, 180.0, 7200.0)] == [
        "under a second", "about 1.2 s", "about 20 s", "about 89 s", "about 3 min",
        "about 2 h"]


# ------------------------------------------------------------------ progress and log lines

def logging_to(stream):
    """A root handler as logging.basicConfig makes in fsi.cli.main, writing to ``stream``."""
    handler = logging.StreamHandler(stream)
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    return handler


def test_log_lines_never_share_a_line_with_the_progress(tmp_path, capsys, monkeypatch):
    """Off a terminal (here a captured stderr, as a log file or a CI log) a record logged in
    the middle of a run is a line of its own, not appended to the bar's."""
    from fsi.procedures import plate_estimate

    real, calls = plate_estimate._fill_record, []

    def logging_record(*args):
        calls.append(1)
        if len(calls) == 2:
            logging.getLogger("fsi.check").info("a record in the middle of the run")
        return real(*args)
    monkeypatch.setattr(plate_estimate, "_fill_record", logging_record)
    handler = logging_to(sys.stderr)
    logging.root.addHandler(handler)
    try:
        assert main(["run", "thesis-plate", "--out", str(tmp_path / "p"), "--no-plots"]) == 0
    finally:
        logging.root.removeHandler(handler)
    lines = capsys.readouterr().err.split("\n")
    assert "INFO fsi.check: a record in the middle of the run" in lines
    assert [line for line in lines if "|" in line and "INFO" in line] == []
    assert any(line.startswith("thesis-plate: 100%|") for line in lines)


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def screen(text: str) -> list[str]:
    """The lines a terminal shows for ``text``: a carriage return goes back to the line's
    start, where what follows overwrites it."""
    shown = []
    for raw in text.split("\n"):
        row, col = [], 0
        for char in raw:
            if char == "\r":
                col = 0
                continue
            row[col:col + 1] = [char]
            col += 1
        shown.append("".join(row).rstrip())
    return shown


def test_on_a_terminal_log_lines_and_warnings_go_above_the_bar(monkeypatch):
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    handler = logging_to(terminal)
    logging.root.addHandler(handler)
    log = logging.getLogger("fsi.check")
    log.setLevel(logging.INFO)
    try:
        with progress_shown("label") as bar:
            assert bar.live
            bar(0.25, "first")
            log.info("a record")
            warnings.warn("a warning", UserWarning)
            bar(1.0, "last")
    finally:
        logging.root.removeHandler(handler)
        log.setLevel(logging.NOTSET)
    lines = [line for line in screen(terminal.getvalue()) if line]
    assert lines[0] == "INFO fsi.check: a record"
    assert lines[1].startswith("WARNING py.warnings: ") and "UserWarning: a warning" in lines[1]
    assert [line for line in lines if "|" in line and ("INFO" in line or "WARN" in line)] == []
    assert lines[-1].startswith("label: 100%|") and lines[-1].endswith("last")


def test_off_a_terminal_progress_is_whole_lines_at_most_every_interval(monkeypatch):
    from fsi import run_job

    stream = io.StringIO()
    clock = iter([0.0, 1.0, 2.0, 40.0, 41.0, 42.0])
    monkeypatch.setattr(run_job.time, "monotonic", lambda: next(clock))
    bar = ProgressBar("label", stream)
    for fraction in (0.1, 0.2, 0.5, 1.0, 1.0):
        bar(fraction, f"at {fraction}")
    bar.close()
    lines = stream.getvalue().split("\n")
    assert [line.split("%")[0] for line in lines] == ["label:   0", "label:  50", "label: 100",
                                                      ""]
    assert "\r" not in stream.getvalue() and lines[1].endswith("at 0.5")


def test_a_sweeps_progress_off_a_terminal_is_a_line_per_case(capsys):
    from types import SimpleNamespace

    from fsi.cli import SweepBar

    bar = SweepBar("s")
    bar.start(2, 1)
    bar.done(SimpleNamespace(name="a"), dict(status=0, seconds=1.0, reason=""))
    bar.done(SimpleNamespace(name="b"), dict(status=1, seconds=2.0, reason="fsi: error: x"))
    bar.close()
    assert capsys.readouterr().err.split("\n") == [
        "s: 1 cases finished before, skipped", "  a: exit 0, 1.0 s [1 of 2 done, 0 failed]",
        "  b: exit 1, 2.0 s (fsi: error: x) [2 of 2 done, 1 failed]", ""]


def test_a_reader_that_stops_early_gets_no_traceback():
    """``fsi scenes | head -0``: when the reader has closed the pipe before fsi writes, fsi
    stops without a traceback on stderr."""
    import subprocess

    proc = subprocess.Popen([sys.executable, "-m", "fsi.cli", "scenes"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    proc.wait(timeout=60)
    assert "Traceback" not in err and "BrokenPipeError" not in err
