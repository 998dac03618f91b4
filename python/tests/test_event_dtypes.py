"""The event log's ``contact`` column is int64 in every route (an adversarial review): it was
uint64 in ``run().events`` and ``load().events`` (``contact - 1`` wrapped around at 0) and
int64 in ``events_to_xarray()``."""

import numpy as np

import beadchain as bc


def test_event_contacts_are_int64(tmp_path):
    out = tmp_path / "s.snap"
    r = bc.run("striker", out=out)
    for events in (r.events, bc.load(out).events):
        c = np.asarray(events["contact"])
        assert c.dtype == np.int64
        assert (c - 1).min() == -1  # contact 0 is logged: no wrap-around
