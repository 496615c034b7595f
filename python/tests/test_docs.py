"""The worked examples of docs/python.md and docs/ensembles.md run as written: every block
fenced as `python` runs, in order, from the repository root, in one namespace per page. A
`python` block followed by a `text` block (after a line "prints") is a doctest: what the block prints must be that
text, where `...` stands for any text (times, paths) and runs of spaces are one."""

import contextlib
import doctest
import io
import os
import re

import pytest

from conftest import ROOT

BLOCK = re.compile(r"^```python\n(.*?)^```\n(?:\n*(?:prints\n\n)?```text\n(.*?)^```)?", re.MULTILINE | re.DOTALL)
CHECKER = doctest.OutputChecker()
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def blocks(page):
    """The page's python blocks, each with the output it shows (None when it shows none)."""
    return [(code, output or None) for code, output in BLOCK.findall((ROOT / "docs" / page).read_text())]


def differences(page):
    """Runs the page's blocks in order; the blocks whose printed output is not the one shown."""
    here = os.getcwd()
    os.chdir(ROOT)
    failures, printed_any = [], False
    try:
        namespace = {"__name__": f"docs_{page}"}
        for i, (code, shown) in enumerate(blocks(page)):
            printed = io.StringIO()
            with contextlib.redirect_stdout(printed):
                exec(compile(code, f"docs/{page} block {i + 1}", "exec"), namespace)
            printed_any |= bool(printed.getvalue())
            if shown is not None and not CHECKER.check_output(shown, printed.getvalue(), FLAGS):
                failures.append(f"docs/{page} block {i + 1} shows\n{shown}but prints\n{printed.getvalue()}")
    finally:
        os.chdir(here)
    assert printed_any, "the examples print what they show"
    return failures


@pytest.mark.parametrize("page", ["python.md", "ensembles.md"])
def test_the_examples_run_and_print_what_they_show(page):
    assert blocks(page), f"docs/{page} has no python block"
    failures = differences(page)
    assert not failures, "\n".join(failures)


def test_python_md_shows_outputs():
    assert sum(shown is not None for _, shown in blocks("python.md")) >= 4, "python.md's doctests"


def test_a_wrong_output_is_caught():
    assert not CHECKER.check_output("<Network: 34 nodes>\n", "<Network: 33 nodes>\n", FLAGS)
    assert CHECKER.check_output("import ... s\n", "import 0.012 s\n", FLAGS)
