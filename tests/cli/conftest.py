"""Fixtures of the command-line tests: a small valid case and a CLI runner."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_cases import BASE_CASE

from fricdamp.cli import main


@pytest.fixture
def base_case() -> str:
    """TOML text of a valid one-DOF case (see BASE_CASE)."""
    return BASE_CASE


@pytest.fixture
def cli(capsys):
    """Call ``fricdamp.cli.main(args)``; return (exit code, stdout, stderr)."""
    def _run(*args) -> tuple[int, str, str]:
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return code, out.out, out.err
    return _run


@pytest.fixture
def write_case(tmp_path):
    """Write TOML text to ``tmp_path / name`` and return the path."""
    def _write(text: str, name: str = "case.toml") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path
    return _write
