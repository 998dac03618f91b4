"""Issue 32 items 7 and 8: `run()` applies `beadchain run`'s output rules (the same library
functions): the estimated-size limit, `[output].frames_max`, and the `[output]` selection of
beads and fields in the Run and in the `out=` file; a failed allocation is a MemoryError."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import beadchain as bc

from conftest import cli_error


def selected_scene(frames_max=None):
    output = {"beads": "0:20:2", "fields": "v"}
    if frames_max is not None:
        output["frames_max"] = frames_max
    return bc.Scene(beads=20, striker=1.0, until=20.0, every=1.0, output=output)


def test_no_output_size_guard_in_run_interpreter_aborts(cli, tmp_path):
    # damped_striker: 100 beads, every = 1; to t = 3e7 that is 3e7 frames of 1648 bytes.
    with pytest.raises(bc.SceneError) as e:
        bc.run(bc.Scene.preset("damped_striker"), until=3e7)
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith("damped_striker: every: the output would be about 46.0 GiB"), msg
    # the CLI's estimate of the same run (same library function)
    cli_msg = cli_error(cli, "run", "damped_striker", "--until", "3e7", "--out",
                        tmp_path / "x.snap")
    assert "the output would be about 46.0 GiB (30000002 frames of 100 beads" in cli_msg
    assert "30000002 frames of 100 beads" in msg and "above the limit of 10.0 GiB" in msg
    for way_out in ("every=", "until=", "output=", "max_output_bytes="):
        assert way_out in msg, msg


def test_no_output_size_guard_in_run_applies_to_the_file_and_to_max_output_bytes(tmp_path):
    s = bc.Scene.preset("damped_striker")
    # at most 102 frames (the estimate) of 100 beads plus the header: about 174.5 KiB
    with pytest.raises(bc.SceneError, match=r"about 174.5 KiB \(102 frames of 100 beads.* above the limit of 64.0 KiB"):
        bc.run(s, out=tmp_path / "x.snap", record=False, max_output_bytes=64 << 10)
    assert not (tmp_path / "x.snap").exists()
    # nothing kept, no file: no size limit (observers only)
    seen = []
    bc.run(s, record=False, max_output_bytes=1, observers=[lambda t, u, v: seen.append(t)])
    assert len(seen) == 101


def test_no_output_size_guard_in_run_fits_the_output_selection():
    # the selection's 10 of 2·20 values fit where every bead does not (CLI: values_per_frame)
    s = selected_scene()
    full = bc.Scene(beads=20, striker=1.0, until=20.0, every=1.0)
    limit = 4096 + 64 * 20 + 5 * 16 + 64 + 22 * (16 + 16 + 8 * 10 + 16)
    assert len(bc.run(s, max_output_bytes=limit).t) == 21
    with pytest.raises(bc.SceneError, match="above the limit"):
        bc.run(full, max_output_bytes=limit)


@pytest.mark.skipif(sys.platform != "linux", reason="ulimit -v is Linux's")
def test_no_output_size_guard_in_run_allocation_failure_is_memoryerror():
    # Under a 4 GB address-space limit the 4.5 GiB of kept frames cannot be allocated: before,
    # Rust aborted the interpreter (SIGABRT, "memory allocation of ... failed").
    code = textwrap.dedent("""
        import beadchain as bc
        try:
            bc.run(bc.Scene.preset("damped_striker"), until=3e6)
        except MemoryError as e:
            print("MemoryError:", e)
    """)
    p = subprocess.run(["bash", "-c", f'ulimit -v 4000000 && exec "{sys.executable}" -c "$0"',
                        code], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])
    assert p.stdout.startswith("MemoryError: run: out of memory keeping frame "), p.stdout
    assert "every=" in p.stdout and "record=False" in p.stdout


def test_output_ignored_by_run_frames_max_refused_as_cli(cli, tmp_path):
    s = selected_scene(frames_max=5)
    path = tmp_path / "x.snap"
    with pytest.raises(bc.SceneError) as e:
        bc.run(s, out=path)
    assert str(e.value) == (
        "scene: output.frames_max: the run would write 21 frames (until = 20, every = 1), "
        "more than frames_max 5; use every=5 or larger, or raise output frames_max"
    )
    assert not path.exists()
    with pytest.raises(bc.SceneError, match="output.frames_max"):
        bc.run(s)  # in memory too
    (tmp_path / "s.toml").write_text(s.source)
    cli_msg = cli_error(cli, "run", tmp_path / "s.toml", "--out", tmp_path / "c.snap")
    assert "would write 21 frames" in cli_msg and "--every 5 or larger" in cli_msg, cli_msg
    # within the cap: runs
    assert len(bc.run(s, every=5.0).t) == 5


def test_output_ignored_by_run_selection_kept_in_run_and_file(cli, tmp_path):
    s = selected_scene()
    path = tmp_path / "x.snap"
    r = bc.run(s, out=path)
    full = bc.run(bc.Scene(beads=20, striker=1.0, until=20.0, every=1.0))
    assert r.u is None
    np.testing.assert_array_equal(r.beads, np.arange(0, 20, 2))
    assert r.v.shape == (21, 10)
    np.testing.assert_array_equal(r.v, full.v[:, 0:20:2])  # bit for bit
    back = bc.load(path)
    assert back.u is None
    np.testing.assert_array_equal(back.beads, r.beads)
    np.testing.assert_array_equal(back.v, r.v)
    # the CLI writes the same frames for the same scene
    (tmp_path / "s.toml").write_text(s.source)
    subprocess.run([cli, "run", tmp_path / "s.toml", "-q", "--out", tmp_path / "c.snap"],
                   check=True, capture_output=True)
    c = bc.load(tmp_path / "c.snap")
    np.testing.assert_array_equal(c.v, r.v)
    np.testing.assert_array_equal(c.beads, r.beads)
