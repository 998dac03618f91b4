"""Issue 32 item 5: every script in examples/ runs, and the numbers it prints are the library's
(`reflected_energy.py` printed the kinetic energy of beads 0..49, 0.285 of E0 at n2 = 2.5,
where `analyze(..., interface=50)` and `validate --quick` give 0.529). Issue 36 item 6: the
notebook examples/tour.ipynb is make_tour.py's output and run_notebook.py's checks pass (and fail
on a wrong number)."""

import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import beadchain as bc

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def run_example(name, *args, cwd=None):
    p = subprocess.run([sys.executable, str(EXAMPLES / name), *args], capture_output=True,
                       text=True, timeout=600, cwd=cwd)
    assert p.returncode == 0, p.stderr[-3000:]
    return p.stdout


def check_reflected_energy(tmp_path):
    out = run_example("reflected_energy.py")
    rows = re.findall(r"^\s*(\d\.\d\d)\s+(\S+)\s+(\d+)$", out, flags=re.M)
    assert len(rows) == 9, out
    base = bc.Scene.preset("interface_3.0_2.5")
    for n2_text, frac_text, steps_text in rows:
        n2 = float(n2_text)
        text = base.source.replace("value = 2.5 }", f"value = {n2!r} }}")
        scene = bc.Scene.from_toml(text, name=f"interface_3.0_{n2}")
        run = bc.run(scene, every=scene.until)
        want = bc.analyze(run, interface=50)["interface"]["reflected_fraction"]
        # printed with 4 significant digits (%.3e): half a unit of the last digit
        assert float(frac_text) == pytest.approx(want, rel=5e-4, abs=0), (n2, out)
        assert int(steps_text) == run.stats["steps"]
        if n2 == 2.5:  # the value: analyze and validate --quick give 0.529 / 0.5277
            assert float(frac_text) == pytest.approx(0.529, abs=1e-3)


def check_interface_spacetime(tmp_path):
    pytest.importorskip("matplotlib")
    out = run_example("interface_spacetime.py", "st.png", cwd=tmp_path)
    assert (tmp_path / "st.png").stat().st_size > 0
    run = bc.run(bc.Scene.preset("interface_3.0_2.5"), every=10.0)
    frames = re.search(r"(\d+) frames of (\d+) beads", out)
    assert frames and (int(frames[1]), int(frames[2])) == run.u.shape, out
    e = run.energy(units="si")["total"]
    m = re.search(r"energy (\S+) J, relative drift (\S+)", out)
    assert m, out
    assert float(m[1]) == pytest.approx(e[0], rel=5e-4, abs=0)     # %.4e
    drift = abs(e[-1] - e[0]) / e[0]
    assert float(m[2]) == pytest.approx(drift, rel=0.05, abs=0)   # %.1e


def needs_jupyter():
    for module in ("nbformat", "nbclient", "ipykernel", "matplotlib"):
        pytest.importorskip(module)


def check_make_tour(tmp_path):
    # the committed notebook is the generator's output, byte for byte (no stored outputs)
    pytest.importorskip("nbformat")
    run_example("make_tour.py", str(tmp_path / "tour.ipynb"))
    assert (tmp_path / "tour.ipynb").read_bytes() == (EXAMPLES / "tour.ipynb").read_bytes(), \
        "examples/tour.ipynb differs from examples/make_tour.py's output: run it again"


def check_run_notebook(tmp_path):
    # run_notebook.py executes tour.ipynb and recomputes every number it prints (see there)
    needs_jupyter()
    out = run_example("run_notebook.py")
    assert out.splitlines()[-1] == "notebook: all checks passed", out
    for part in ("part 1: reflected_fraction=", "part 2: ", "part 3: events="):
        assert part in out, out


CHECKS = {
    "reflected_energy.py": check_reflected_energy,
    "interface_spacetime.py": check_interface_spacetime,
    "make_tour.py": check_make_tour,
    "run_notebook.py": check_run_notebook,
}


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.py")))
def test_example_prints_the_wrong_physics(name, tmp_path):
    assert name in CHECKS, f"examples/{name} has no check of its printed numbers in {__file__}"
    CHECKS[name](tmp_path)


def test_the_notebook_checker_fails_on_a_wrong_number(tmp_path):
    # the notebook split at bead 51 instead of 50: reflected 0.5292558 instead of 0.5292547
    needs_jupyter()
    text = (EXAMPLES / "tour.ipynb").read_text()
    assert text.count('interface=50)[\\"interface\\"]') == 1
    (tmp_path / "wrong.ipynb").write_text(
        text.replace('interface=50)[\\"interface\\"]', 'interface=51)[\\"interface\\"]'))
    p = subprocess.run([sys.executable, str(EXAMPLES / "run_notebook.py"), "--notebook",
                        str(tmp_path / "wrong.ipynb")], capture_output=True, text=True, timeout=600)
    assert p.returncode != 0 and "AssertionError: reflected_fraction: notebook" in p.stderr, \
        p.stdout + p.stderr[-3000:]
