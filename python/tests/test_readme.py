"""The README's code blocks run as written: every `sh` command and every line of the `python`
block, from the repository root, except the ones in EXEMPT (each with the reason). `cargo xtask
run` and `cargo xtask diff` are `karstgen run` and `karstgen diff` (the same code), so they run
as the `karstgen` command of this workspace (KARSTGEN_BIN)."""

import os
import re
import shlex
import subprocess

import pytest

from conftest import ROOT

BLOCK = re.compile(r"^```(sh|python)\n(.*?)^```", re.MULTILINE | re.DOTALL)

# The commands and lines the test does not run, and why: exact commands, then starts of lines.
EXEMPT = {
    "cargo xtask run": "the embedded default scene: minutes for every stage",
    "karstgen run": "the embedded default scene: minutes for every stage",
    "karstgen run path/to/scene.toml": "a placeholder path",
    "cargo install --path .": "installs into ~/.cargo/bin, outside the checkout",
}
EXEMPT_STARTS = {
    "cargo xtask test": "the test suite itself",
    "karstgen view out/default --serve": "serves until stopped (test_view_serve.py serves tiny's run)",
    "pip install": "the test venv installs the wheel itself (cargo xtask test)",
    "karstgen diff out/a/": "placeholder runs a and b",
    "karstgen metrics --karstnet path/to/": "a placeholder path",
    "cargo xtask bless": "the goldens' own review (tests/tests/golden.rs checks what it records)",
    "cargo xtask bench": "benchmarks: minutes to hours",
    "karstgen export out/default": "needs the default scene's run (minutes)",
    "karstgen.ensemble(": "200 realizations on Dask: minutes (the ensemble tests run small ones)",
}


def blocks():
    return BLOCK.findall((ROOT / "README.md").read_text())


def exempt(line):
    return line in EXEMPT or any(line.startswith(start) for start in EXEMPT_STARTS)


def commands():
    lines = []
    for kind, body in blocks():
        if kind != "sh":
            continue
        for line in body.splitlines():
            command = line.split("  #")[0].strip()
            if command:
                lines.append(command)
    return lines


def test_every_exemption_is_used():
    lines = commands() + [l for kind, b in blocks() if kind == "python" for l in b.splitlines()]
    lines = [l.strip() for l in lines]
    unused = [c for c in EXEMPT if c not in lines]
    unused += [start for start in EXEMPT_STARTS if not any(l.startswith(start) for l in lines)]
    assert not unused, f"exemptions matching no README line: {unused}"


@pytest.mark.parametrize("command", [c for c in commands() if not exempt(c)])
def test_the_sh_commands_run(command):
    words = shlex.split(command)
    if words[:3] in (["cargo", "xtask", "run"], ["cargo", "xtask", "diff"]):
        words = ["karstgen", *words[2:]]
    assert words[0] == "karstgen", f"not runnable and not exempt: {command}"
    binary = os.environ.get("KARSTGEN_BIN")
    assert binary, "set KARSTGEN_BIN (cargo xtask test does this)"
    result = subprocess.run([binary, *words[1:]], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, f"{command}\n{result.stderr}"


def test_the_python_block_runs():
    (code,) = [b for kind, b in blocks() if kind == "python"]
    kept = "\n".join(l for l in code.splitlines() if not exempt(l.strip()))
    here = os.getcwd()
    os.chdir(ROOT)
    try:
        exec(compile(kept, "README.md python block", "exec"), {"__name__": "readme"})
    finally:
        os.chdir(here)
