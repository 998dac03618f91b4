"""Issue 32 item 11: NumPy 0-d arrays and masked arrays as Scene/run values: a 0-d array is a
scalar; a masked array is its data unless a value is masked, which is refused naming the key."""

import numpy as np
import pytest

import beadchain as bc


def test_numpy_0d_and_masked_arrays_unclear_typeerror_scalar_keys():
    a = bc.Scene(beads=np.array(10), exponent=np.array(2.5), striker=np.array(1.0),
                 until=np.array(5.0), every=np.float64(1.0))
    b = bc.Scene(beads=10, exponent=2.5, striker=1.0, until=5.0, every=1.0)
    assert a == b
    r = bc.run(b, every=np.array(2.5), until=np.array(5.0), rtol=np.array(1e-9))
    np.testing.assert_array_equal(r.t, [0.0, 2.5, 5.0])
    sim = bc.Simulation(b, every=np.array(1.0))
    assert sim.advance(np.array(2.0)).t == 2.0


def test_numpy_0d_and_masked_arrays_unclear_typeerror_unmasked_data_used():
    m = np.ma.masked_array(np.ones(10), mask=np.zeros(10, bool))
    a = bc.Scene(mass=m, striker=1.0, until=5.0)
    np.testing.assert_array_equal(a.chain.mass, np.ones(10))


def test_numpy_0d_and_masked_arrays_unclear_typeerror_masked_value_refused():
    m = np.ma.masked_array(np.ones(10), mask=[False] * 3 + [True] + [False] * 6)
    with pytest.raises(bc.SceneError) as e:
        bc.Scene(mass=m, striker=1.0, until=5.0)
    assert str(e.value) == (
        "scene: [chain].mass: expected numbers, got a masked array with 1 masked value(s) "
        "(first at index 3); fill them (.filled(x)) or leave them out")
    with pytest.raises(bc.SceneError, match=r"^scene: \[run\].until: expected numbers, got a "
                       "masked array with 1 masked"):
        bc.Scene(beads=10, striker=1.0, until=np.ma.masked)
    with pytest.raises(bc.SceneError, match=r"^every: expected numbers, got a masked array"):
        bc.run(bc.Scene(beads=10, striker=1.0, until=5.0), every=np.ma.masked_array(1.0, True))
    sim = bc.Simulation(bc.Scene(beads=3, striker=1.0, until=5.0))
    with pytest.raises(bc.SceneError, match=r"^scene: set_velocities: v: expected numbers, got a "
                       r"masked array with 1 masked value\(s\) \(first at index 2\)"):
        sim.set_velocities(np.ma.masked_array([1.0, 0.0, 0.0], mask=[0, 0, 1]))


def test_numpy_0d_and_masked_arrays_unclear_typeerror_wrong_shape_names_key():
    with pytest.raises(TypeError) as e:
        bc.Scene(mass=np.ones((2, 5)), striker=1.0, until=5.0)
    assert str(e.value) == ("scene: [chain].mass: expected a number or a 1-D array (one value "
                            "per bead or contact), got an array of shape (2, 5)")
    with pytest.raises(TypeError, match=r"^scene: \[walls\].right.exponent: expected a number"):
        bc.Scene(beads=4, striker=1.0, until=5.0, walls={"right": {"exponent": np.ones((1, 1))}})
    with pytest.raises(TypeError, match=r"^every: expected a number, got an array of shape \(2,\)"):
        bc.run(bc.Scene(beads=10, striker=1.0, until=5.0), every=np.array([1.0, 2.0]))
    with pytest.raises(TypeError, match=r"^scene: \[initial\].striker: expected a number, "
                       "string, array, list or dict, got object"):
        bc.Scene(beads=10, striker=object(), until=5.0)
