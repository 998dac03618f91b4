"""The event log's ``contact`` column is int64 in every route (an adversarial review): it was
uint64 in ``run().events`` and ``load().events`` (``contact - 1`` wrapped around at 0) and
int64 in ``events_to_xarray()``."""

import numpy as np
import pytest

import beadchain as bc


def test_event_contacts_are_int64(tmp_path):
    out = tmp_path / "s.snap"
    r = bc.run("striker", out=out)
    for events in (r.events, bc.load(out).events):
        c = np.asarray(events["contact"])
        assert c.dtype == np.int64
        assert (c - 1).min() == -1  # contact 0 is logged: no wrap-around


def test_event_attributes_say_their_si_conversion():
    # before: rel_velocity and peak_overlap had units "1" and no SI note (u, v and time had)
    pytest.importorskip("xarray")
    ds = bc.run("striker").events_to_xarray()
    assert ds.rel_velocity.attrs["note"] == "SI: v / beta (m/s)"
    assert ds.peak_overlap.attrs["note"] == "SI: metres, unchanged"
