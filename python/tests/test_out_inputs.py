"""An ``out=`` file may not replace an input, as the CLI refuses (``beadchain run --out``,
``beadchain sweep --out``). Before, ``run(out=)`` replaced its own scene file (or a CSV file
the scene reads) with the snapshot, and ``sweep(out=)`` ran every point and then replaced the
sweep file or its base scene with the result CSV."""

import pytest

import beadchain as bc

TINY = "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\n"


def _files(d):
    (d / "s.toml").write_text(TINY)
    (d / "c.toml").write_text(TINY.replace("beads = 4\n", 'beads = 4\nmass = { file = "m.csv" }\n'))
    (d / "m.csv").write_text("1\n1\n1\n1\n")
    (d / "sw.toml").write_text('scene = "s.toml"\n[grid]\n"chain.exponent" = [2.5, 3.0]\n')
    return {f: (d / f).read_bytes() for f in ("s.toml", "c.toml", "m.csv", "sw.toml")}


def test_run_out_may_not_replace_the_scene_or_its_csv(tmp_path):
    keep = _files(tmp_path)
    cases = [
        (str(tmp_path / "s.toml"), tmp_path / "s.toml", "scene file"),
        (bc.Scene.from_toml(tmp_path / "s.toml"), tmp_path / "s.toml", "scene file"),
        (str(tmp_path / "c.toml"), tmp_path / "m.csv", "CSV file"),
    ]
    for scene, out, kind in cases:
        with pytest.raises(bc.SceneError, match=f"out: is the {kind} .* refusing to overwrite"):
            bc.run(scene, out=out)
    for f, b in keep.items():
        assert (tmp_path / f).read_bytes() == b, f
    bc.run(str(tmp_path / "s.toml"), out=tmp_path / "o.snap")  # any other name is written
    assert (tmp_path / "o.snap").read_bytes()[:7] == b"BEADCHN"


def test_sweep_out_may_not_replace_its_inputs(tmp_path):
    keep = _files(tmp_path)
    sw = tmp_path / "sw.toml"
    for out, kind in [(sw, "sweep file"), (tmp_path / "s.toml", "scene file"),
                      (tmp_path / "s", "scene file")]:
        if out.name == "s":  # out.meta would be s.meta: make that the base scene
            (tmp_path / "s.meta").write_text(TINY)
            (tmp_path / "sw2.toml").write_text(
                'scene = "s.meta"\n[grid]\n"chain.exponent" = [2.5, 3.0]\n')
            path = tmp_path / "sw2.toml"
        else:
            path = sw
        progress = []
        with pytest.raises(bc.SceneError, match=f"out: is the {kind} .* refusing to overwrite"):
            bc.sweep(path, out=out, progress=lambda done, total: progress.append(done))
        assert progress == [], "refused before any run"
    for f, b in keep.items():
        assert (tmp_path / f).read_bytes() == b, f
    assert (tmp_path / "s.meta").read_text() == TINY
