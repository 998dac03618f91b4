"""Issue 34: ``Scene(**kwargs)`` passes its values to the scene parser as tables (no TOML text in
between): the same resolved scene, bit for bit, as the equivalent TOML text, the same messages,
and a source that ``with_overrides``, pickling and ``Chain.radius`` still read."""

import copy
import math
import pickle
import re

import numpy as np
import pytest

import beadchain as bc


def arr(a) -> str:
    """A TOML array of floats, every digit kept (``repr`` round-trips)."""
    return "[" + ", ".join(repr(float(x)) for x in a) + "]"


RNG = np.random.default_rng(1)
MASS = 1.0 + RNG.random(50)          # values that need all 17 significant digits
PREFACTOR = 0.5 + RNG.random(49)
VELOCITY = 0.1 * RNG.random(50)
RADIUS = 4e-3 * (1.0 + 0.1 * RNG.random(30))


def dimensionless():
    kw = dict(name="mixed", seed=7, mass=MASS, prefactor=PREFACTOR, velocity=VELOCITY,
              exponent={"base": 3.0, "segments": [{"from": 20, "value": 2.5}]},
              precompression=np.float64(1e-3), striker=0.5,
              walls={"right": {"exponent": 2.5, "prefactor": 1.5}, "left": None},
              until=6.0, every=1.5, rtol=1e-10)
    text = (f"[scene]\nname = \"mixed\"\nseed = 7\n"
            f"[chain]\nmass = {arr(MASS)}\nprefactor = {arr(PREFACTOR)}\n"
            "exponent = { base = 3.0, segments = [{ from = 20, value = 2.5 }] }\n"
            "precompression = 0.001\n"
            f"[initial]\nvelocity = {arr(VELOCITY)}\nstriker = 0.5\n"
            "[run]\nuntil = 6.0\nevery = 1.5\nrtol = 1e-10\n"
            "[walls]\nright = { exponent = 2.5, prefactor = 1.5 }\n")
    return kw, text


def physical():
    units = {"system": "physical", "radius": RADIUS, "young": 2.26e11, "poisson": 0.3,
             "density": 7650.0, "n0": 2.5}
    kw = dict(beads=30, units=units, exponent=2.5, striker_si=0.11, until=200.0, every=50.0)
    text = (f"[units]\nsystem = \"physical\"\nradius = {arr(RADIUS)}\nyoung = 2.26e11\n"
            "poisson = 0.3\ndensity = 7650.0\nn0 = 2.5\n"
            "[chain]\nbeads = 30\nexponent = 2.5\n[initial]\nstriker_si = 0.11\n"
            "[run]\nuntil = 200.0\nevery = 50.0\n")
    return kw, text


def same_run(a, b):
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.u, b.u)
    np.testing.assert_array_equal(a.v, b.v)
    assert a.u[-1].tobytes() == b.u[-1].tobytes() and a.v[-1].tobytes() == b.v[-1].tobytes()


@pytest.mark.parametrize("make", [dimensionless, physical])
def test_kwargs_scene_equals_the_toml_text_scene_bit_for_bit(make):
    kw, text = make()
    a = bc.Scene(**kw)
    b = bc.Scene.from_toml(text, name=kw.get("name"))
    assert a == b
    assert a.name == b.name and a.warnings == b.warnings
    for x, y in ((a.chain.mass, b.chain.mass), (a.chain.prefactor, b.chain.prefactor),
                 (a.v0, b.v0), (a.u0, b.u0)):
        assert x.tobytes() == y.tobytes()
    # the source is TOML of the same tables: it parses back to the same scene
    assert bc.Scene.from_toml(a.source, name=kw.get("name")) == a
    same_run(bc.run(a), bc.run(b))


def test_kwargs_values_arrive_exactly():
    kw, _ = dimensionless()
    s = bc.Scene(**kw)
    assert s.chain.mass.tobytes() == MASS.tobytes()
    assert s.chain.prefactor.tobytes() == PREFACTOR.tobytes()
    assert s.v0[1:].tobytes() == VELOCITY[1:].tobytes() and s.v0[0] == 0.5
    assert s.chain.right_wall["prefactor"] == 1.5 and s.chain.left_wall is None


def test_per_bead_radius_of_a_kwargs_scene_comes_back_exactly():
    kw, _ = physical()
    s = bc.Scene(**kw)
    assert s.chain.radius.tobytes() == RADIUS.tobytes()
    back = pickle.loads(pickle.dumps(s))
    assert back == s and back.source == s.source
    assert back.chain.radius.tobytes() == RADIUS.tobytes()


@pytest.mark.parametrize("kw,text", [
    ({"beads": 10, "until": float("nan")}, "[chain]\nbeads = 10\n[run]\nuntil = nan\n"),
    ({"beads": 10, "until": float("inf")}, "[chain]\nbeads = 10\n[run]\nuntil = inf\n"),
    ({"mass": [1.0, -math.inf, 1.0], "until": 5.0},
     "[chain]\nmass = [1.0, -inf, 1.0]\n[run]\nuntil = 5.0\n"),
    ({"mass": np.array([1.0, 1.0, np.nan]), "until": 5.0},
     "[chain]\nmass = [1.0, 1.0, nan]\n[run]\nuntil = 5.0\n"),
    ({"beads": 10, "until": 5.0, "walls": {"right": {"exponnt": 2.5}}},
     "[chain]\nbeads = 10\n[run]\nuntil = 5.0\n[walls]\nright = { exponnt = 2.5 }\n"),
    ({"beads": 10, "until": 5.0, "units": {"system": "physical", "radius": "big"}},
     "[chain]\nbeads = 10\n[run]\nuntil = 5.0\n[units]\nsystem = \"physical\"\n"
     "radius = \"big\"\n"),
    ({"beads": 10, "until": 5.0,
      "exponent": {"base": 3.0, "segments": [{"from": 2, "valu": 2.5}]}},
     "[chain]\nbeads = 10\nexponent = { base = 3.0, segments = [{ from = 2, valu = 2.5 }] }\n"
     "[run]\nuntil = 5.0\n"),
    ({"beads": 10, "until": 5.0, "method": "euler"},
     "[chain]\nbeads = 10\n[run]\nuntil = 5.0\nmethod = \"euler\"\n"),
    ({"beads": 10, "until": 5.0, "seed": -1}, "[scene]\nseed = -1\n[chain]\nbeads = 10\n"
     "[run]\nuntil = 5.0\n"),
])
def test_bad_keys_and_values_get_the_text_scenes_message(kw, text):
    with pytest.raises(bc.SceneError) as a:
        bc.Scene(**kw)
    with pytest.raises(bc.SceneError) as b:
        bc.Scene.from_toml(text)
    assert str(a.value) == str(b.value)
    assert str(a.value).startswith("scene: [") and "\n" not in str(a.value)


def test_values_that_are_not_toml_raise_type_error_naming_the_key():
    with pytest.raises(TypeError, match=r"^scene: \[walls\].right.exponent: None is not a value"):
        bc.Scene(beads=4, until=5.0, walls={"right": {"exponent": None}})
    with pytest.raises(TypeError, match=r"^mine: \[chain\].mass\[1\]: None is not a value"):
        bc.Scene(name="mine", mass=[1.0, None], until=5.0)
    with pytest.raises(TypeError, match=r"^scene: \[chain\].beads: the integer \d+ does not fit"):
        bc.Scene(beads=2**70, until=5.0)
    with pytest.raises(TypeError, match=r"^scene: \[chain\].mass: dict keys must be strings"):
        bc.Scene(beads=4, mass={1: 2.0}, until=5.0)
    with pytest.raises(TypeError, match=r"^scene: \[chain\].mass: expected a number, string, "
                       "array, list or dict, got set"):
        bc.Scene(mass={1.0}, until=5.0)


def test_numpy_ints_bools_and_nested_builders():
    a = bc.Scene(mass=np.arange(1, 11), exponent=np.array([2.5] * 9, dtype=np.float32),
                 walls={"right": {"hard": np.bool_(True), "restitution": 1.0}},
                 striker=1.0, until=5.0)
    b = bc.Scene.from_toml(
        "[chain]\nmass = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n"
        f"exponent = [{', '.join(['2.5'] * 9)}]\n"
        "[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\n"
        "[walls]\nright = { hard = true, restitution = 1.0 }\n")
    assert a == b
    assert a.chain.right_wall["hard"] is True
    np.testing.assert_array_equal(a.chain.mass, np.arange(1.0, 11.0))
    c = bc.Scene(beads=12, radius={"base": np.float64(1.0),
                                   "taper": {"q": 0.05, "from": np.int64(4)}},
                 striker=1.0, until=5.0, every=np.float32(0.5))
    d = bc.Scene.from_toml(
        "[chain]\nbeads = 12\nradius = { base = 1.0, taper = { q = 0.05, from = 4 } }\n"
        "[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\nevery = 0.5\n")
    assert c == d
    assert c.chain.mass[4] == 1.0 and c.chain.mass[5] == pytest.approx(0.95**3, rel=1e-14)


def test_none_keys_are_left_out_and_empty_tables_too():
    base = bc.Scene(beads=10, striker=1.0, until=5.0)
    assert bc.Scene(beads=10, striker=1.0, until=5.0, rtol=None, force=None) == base
    assert bc.Scene(beads=10, striker=1.0, until=5.0, walls={}, hard={}) == base
    assert "[walls]" not in base.source and "[field]" not in base.source


def test_with_overrides_of_a_kwargs_scene():
    kw, _ = dimensionless()
    s = bc.Scene(**kw)
    t = s.with_overrides({"chain.exponent.segments.0.value": 2.4, "run.until": 3.0})
    kw2 = dict(kw, until=3.0, exponent={"base": 3.0, "segments": [{"from": 20, "value": 2.4}]})
    assert t == bc.Scene(**kw2)
    assert t.name == "mixed" and t.chain.mass.tobytes() == MASS.tobytes()
    assert s == bc.Scene(**kw)  # the original is left alone


def test_pickle_and_copy_of_a_kwargs_scene():
    kw, _ = dimensionless()
    s = bc.Scene(**kw)
    for back in (pickle.loads(pickle.dumps(s)), copy.deepcopy(s)):
        assert back == s and back.source == s.source and back.warnings == s.warnings
        assert back.with_overrides({"scene.seed": 8}).seed == 8


def _parser_keys(table):
    """The keys the scene parser accepts in ``[table]`` (its unknown-key message lists them)."""
    with pytest.raises(bc.SceneError) as e:
        bc.Scene.from_toml(f"[{table}]\nnot_a_key = 1\n")
    m = re.search(r"\[" + table + r"\]\.not_a_key: unknown key \(expected one of: ([^)]*)\)",
                  str(e.value))
    assert m, str(e.value)
    return set(m.group(1).split(", "))


def test_documented_scene_keys_rejected_by_scene_kwargs():
    # every key the parser accepts is a keyword of Scene(...), in its table
    from beadchain._scene import _KEYS
    for table, keys in _KEYS.items():
        assert set(keys) == _parser_keys(table), table
    s = bc.Scene(beads=5, precompression_force=0.1, until=5.0)
    assert s == bc.Scene.from_toml("[chain]\nbeads = 5\nprecompression_force = 0.1\n"
                                   "[run]\nuntil = 5.0\n")
    preset = bc.Scene.preset("dimer_dispersion")
    kw = bc.Scene(name=preset.name, description=preset.description, beads=40,
                  mass={"alternate": [1.0, 0.5]}, precompression_force=0.1,
                  walls={"left": {}, "right": {}}, equilibrium=True,
                  mode={"index": 20, "amplitude": 1e-4}, until=100.0, every=0.5)
    assert kw == preset


def test_wrong_exception_types_scene_units_none():
    # keys whose value is None are left out, whole tables too
    base = bc.Scene(beads=10, striker=1.0, until=5.0)
    for table in ("units", "walls", "hard", "output"):
        assert bc.Scene(beads=10, striker=1.0, until=5.0, **{table: None}) == base
    assert "[units]" not in bc.Scene(beads=10, striker=1.0, until=5.0, units=None).source
    with pytest.raises(TypeError, match="unexpected keyword 'unit'"):
        bc.Scene(beads=10, striker=1.0, until=5.0, unit=None)
