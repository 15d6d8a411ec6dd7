"""The figures the docs quote are fresh: every deterministic figure of scripts/make-figures.py
(file sizes of deterministic outputs, counts, solver numbers) recomputed from its command and
compared with the quoted text, at the quoted precision. Timings and memory peaks are not
checked (they are not deterministic): `python3 scripts/make-figures.py --write` re-measures
them. A stale figure fails naming its document, line, quoted and fresh value.
"""

import importlib.util

import pytest

from conftest import ROOT, checker

spec = importlib.util.spec_from_file_location("make_figures", ROOT / "scripts" / "make-figures.py")
figures = importlib.util.module_from_spec(spec)
spec.loader.exec_module(figures)

DETERMINISTIC = [f for f in figures.FIGURES if f.deterministic]
TEXTS = {doc: (ROOT / doc).read_text() for doc in {f.doc for f in figures.FIGURES}}


@pytest.fixture(scope="module")
def runs(grasp_bin, tmp_path_factory):
    """The figures' runs, each made once for the module, with the CLI under test."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("GRASP_BIN", grasp_bin)
        yield figures.Runs(tmp_path_factory.mktemp("figures"))


def test_every_figure_is_quoted_once_where_its_pattern_says():
    for f in figures.FIGURES:
        figures.find(f, TEXTS[f.doc])


@pytest.mark.parametrize("doc", sorted({f.doc for f in DETERMINISTIC}))
def test_quoted_deterministic_figures_are_fresh(doc, runs):
    if any(f.run == "mujoco_handoff" for f in DETERMINISTIC if f.doc == doc):
        checker("mujoco", reason="MuJoCo is not installed (scripts/install-checkers.sh installs mujoco==4.0.0)")
    stale = figures.stale_figures(TEXTS, runs, [f for f in DETERMINISTIC if f.doc == doc])
    assert not stale, "stale figures (refresh: python3 scripts/make-figures.py --write):\n" + "\n".join(map(str, stale))


def test_a_stale_quoted_figure_fails_naming_its_document_line_and_fresh_value(runs):
    # The defect: the docs quoted a 10.6 MB fine-patch recording, and nothing noticed when it
    # grew. A quoted size that is not the fresh one is reported, with where it is quoted.
    figure = next(f for f in figures.FIGURES if f.name == "fine-patch recording size")
    fresh = figure.value(runs.get(figure.run))
    quote = figures.find(figure, TEXTS[figure.doc])
    wrong = "10.6" if fresh != "10.6" else "24.1"
    text = TEXTS[figure.doc][:quote.start] + wrong + TEXTS[figure.doc][quote.end:]
    stale = figures.stale_figures({figure.doc: text}, runs, [figure])
    assert [str(s) for s in stale] == [
        f"docs/guide/outputs.md:{quote.line}: fine-patch recording size: quoted {wrong}, fresh {fresh}"]
    # Rewriting puts the fresh value back where it was quoted, and nothing else changes.
    assert figures.rewrite(text, [(s.quote.start, s.quote.end, s.fresh) for s in stale]) == \
        text[:quote.start] + fresh + text[quote.start + len(wrong):]


def test_a_figure_quoted_twice_or_not_at_all_is_an_error_naming_the_document():
    figure = next(f for f in figures.FIGURES if f.name == "fine-patch MCAP size")
    for text in ["no figure here", "writes a 1.0 MB MCAP, writes a 2.0 MB MCAP"]:
        with pytest.raises(LookupError, match="docs/guide/outputs.md: figure fine-patch MCAP size"):
            figures.find(figure, text)


def test_the_long_marker_follows_the_measured_time():
    marker = figures.LongMarker("doc.md", "grasp plan --slow", "plan")
    plain = "text\n\n```console\n$ grasp plan --slow\n```\n"
    marked = "text\n\n<!-- doc-test: long -->\n```console\n$ grasp plan --slow\n```\n"
    assert figures.long_marker_edit(plain, marker, 25.0) == marked
    assert figures.long_marker_edit(marked, marker, 25.0) == marked
    assert figures.long_marker_edit(marked, marker, 1.3) == plain
    assert figures.long_marker_edit(plain, marker, 1.3) == plain


def test_the_readme_test_count_comes_from_the_test_commands_closing_line():
    readme = "`677 passed, 0 failed` (27 November); now `760 passed, 0 failed` (28 November, CI: 376 s). The"
    new = figures.test_count_edit(readme, "test result: ok\n771 passed, 0 failed\n")
    assert new.startswith("`677 passed, 0 failed` (27 November); now `771 passed, 0 failed` (")
    assert new.endswith(", counted by\n  `scripts/make-figures.py --test-log` from the test command's log). The")
    with pytest.raises(RuntimeError, match="2 failures"):
        figures.test_count_edit(readme, "769 passed, 2 failed\n")
