"""Fixtures of the command-line tests: a small valid case, a CLI runner and the check of a
rejected case (exit code 2, one clear line)."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_cases import BASE_CASE

from fricdamp.cli.app import main


@pytest.fixture
def base_case() -> str:
    """TOML text of a valid one-DOF case (see BASE_CASE)."""
    return BASE_CASE


@pytest.fixture
def cli(capsys):
    """Call ``fricdamp.cli.app.main(args)``; return (exit code, stdout, stderr)."""
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


@pytest.fixture
def assert_rejected(cli, write_case):
    """Check that ``fricdamp <command>`` rejects a case as invalid input.

    ``assert_rejected(text, expected, commands=("check",))`` writes ``text`` as a case file and runs
    each command on it (``run`` with ``--out <tmp>/out``). Each must exit with code 2 and write
    one line to stderr, without a traceback or "internal error", containing every substring of
    ``expected``; every command must write the same stderr, and ``run`` must write nothing.
    Returns the line.
    """
    def _rejects(text: str, expected, commands=("check",)) -> str:
        path = write_case(text)
        out_dir = path.parent / "out"
        errs = []
        for command in commands:
            args = ("--out", out_dir) if command == "run" else ()
            code, out, err = cli(command, path, *args)
            assert code == 2, (command, out, err)
            line = err.strip()
            assert line and "\n" not in line, err
            assert "Traceback" not in line and "internal error" not in line, err
            for piece in expected:
                assert piece in line, (command, piece, line)
            assert not out_dir.exists(), f"{command} wrote {out_dir}"
            errs.append(err)
        assert all(e == errs[0] for e in errs), errs
        return errs[0].strip()
    return _rejects
