"""``python -m fricdamp`` runs the command line, and ``--help`` names documentation that exists
in an installed package (not a source-tree path the wheel does not ship)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path


def _run(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "CI": "1"}
    return subprocess.run([sys.executable, "-m", "fricdamp", *args], capture_output=True,
                          text=True, env=env, timeout=120)


def test_python_m_fricdamp_runs_the_cli(tmp_path):
    proc = _run("--version")
    assert proc.returncode == 0 and proc.stdout.startswith("fricdamp ")
    proc = _run("frobnicate")
    assert proc.returncode == 2 and "invalid choice" in proc.stderr
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n', encoding="utf-8")
    proc = _run("check", str(bad))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr


def test_help_points_to_files_that_exist(cli):
    code, out, _ = cli("--help")
    assert code == 0
    assert "python -m fricdamp" in out
    # every file path the help names exists in the installed package
    paths = re.findall(r"(/\S+\.toml)", out)
    assert paths and all(Path(p).is_file() for p in paths)
    assert "demo.toml" in out
    assert not re.search(r"(?<![\w/])docs/cases\.md(?! of the source tree)", out)
