"""Shared fixtures: the CLI binary (for comparisons with what the CLI writes and prints)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Path of the `beadchain` binary: $BEADCHAIN_CLI (must exist when set, as in CI), else
    target/release/beadchain of this checkout (tests are skipped when it was not built)."""
    env = os.environ.get("BEADCHAIN_CLI")
    if env:
        assert os.path.exists(env), f"BEADCHAIN_CLI={env} does not exist"
        return env
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    path = os.path.join(target, "release", "beadchain")
    if not os.path.exists(path):
        pytest.skip("the beadchain CLI is not built (cargo build --release)")
    return path


def run_cli(cli, *args, cwd=None):
    """Runs the CLI; returns (exit code, stdout, stderr)."""
    p = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    return p.returncode, p.stdout, p.stderr


def cli_error(cli, *args, cwd=None):
    """The CLI's one-line error for `args` without the `beadchain: error: ` prefix (exit 2)."""
    code, _, err = run_cli(cli, *args, cwd=cwd)
    assert code == 2, err
    lines = [l for l in err.splitlines() if l.startswith("beadchain: error: ")]
    assert len(lines) == 1, err
    return lines[0][len("beadchain: error: "):]
