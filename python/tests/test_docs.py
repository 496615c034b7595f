"""The worked examples of docs/python.md and docs/ensembles.md run as written: every block
fenced as `python` runs, in order, from the repository root, in one namespace per page."""

import os
import re

import pytest

from conftest import ROOT

BLOCK = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks(page):
    return BLOCK.findall((ROOT / "docs" / page).read_text())


@pytest.mark.parametrize("page", ["python.md", "ensembles.md"])
def test_the_examples_run(page, capsys):
    code = blocks(page)
    assert code, f"docs/{page} has no python block"
    here = os.getcwd()
    os.chdir(ROOT)
    try:
        namespace = {"__name__": f"docs_{page}"}
        for i, block in enumerate(code):
            exec(compile(block, f"docs/{page} block {i + 1}", "exec"), namespace)
    finally:
        os.chdir(here)
    assert capsys.readouterr().out, "the examples print what they show"
