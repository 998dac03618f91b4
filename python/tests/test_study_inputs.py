"""The study functions refuse what the CLI refuses (an adversarial review): before,
``equilibrium(force=nan)`` returned NaN arrays without an exception, ``modes(window=(nan, 1))``
and ``window=(5, 1)`` were accepted, and ``breather`` with a frequency of nan, -1, inf or 0, a
zero step or a NaN seed amplitude failed late with a continuation or engine error."""

import math

import pytest

import beadchain as bc


@pytest.mark.parametrize("force", [math.nan, math.inf, -math.inf])
def test_equilibrium_refuses_a_non_finite_force(force):
    with pytest.raises(bc.SceneError, match="equilibrium: force = .*: expected a finite force"):
        bc.equilibrium("dimer_dispersion", force=force)


@pytest.mark.parametrize("window", [(math.nan, 1.0), (5.0, 1.0), (-1.0, 1.0), (0.0, math.inf)])
def test_modes_refuses_a_bad_window(window):
    with pytest.raises(bc.SceneError, match="modes: window = .*: expected finite frequencies"):
        bc.modes("dimer_dispersion", window=window)


@pytest.mark.parametrize("key,value", [("frequency", math.nan), ("frequency", -1.0),
                                       ("frequency", math.inf), ("frequency", 0.0),
                                       ("step", 0.0), ("seed_amplitude", math.nan),
                                       ("tol", -1e-9), ("periods", 0.0)])
def test_breather_refuses_bad_settings_before_any_work(key, value):
    kwargs = {"frequency": 2.0, key: value}
    with pytest.raises(bc.SceneError, match=f"breather: {key} = .*: expected a finite value > 0"):
        bc.breather("dimer_gap_breather", **kwargs)


@pytest.mark.parametrize("bad", [None, b"[chain]\nbeads = 3\n", 3])
def test_scene_from_toml_refuses_what_is_neither_path_nor_text(bad):
    # before: parsed as TOML text ("malformed TOML")
    with pytest.raises(TypeError, match="Scene.from_toml: expected a path or TOML text"):
        bc.Scene.from_toml(bad)
