"""A sweep on a Dask cluster (issue 36, item 3): `bc.sweep(path, executor=client.get_executor(),
out=OUT)` on a `distributed.LocalCluster` of 2 worker processes writes the CLI's result file bit
for bit. Skipped without dask.distributed (CI installs it: .ci/run)."""

import time

import pytest

import beadchain as bc
from conftest import ROOT, run_cli

distributed = pytest.importorskip("distributed")

GRID = ROOT / "data" / "sweeps" / "reflection_grid.toml"


def test_sweep_on_a_local_cluster_gives_the_clis_csv(cli, tmp_path):
    code, _, err = run_cli(cli, "sweep", GRID, "--out", tmp_path / "cli.csv")
    assert code == 0, err
    t0 = time.perf_counter()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        with distributed.get_task_stream(client) as ts:
            table = bc.sweep(GRID, executor=client.get_executor(), out=tmp_path / "dask.csv")
        # every point ran as a task on the cluster's workers
        assert len(client.scheduler_info()["workers"]) == 2
        assert len(ts.data) == 9 and {d["worker"] for d in ts.data} <= set(
            client.scheduler_info()["workers"])
    elapsed = time.perf_counter() - t0
    assert (table.skipped, table.ran) == (0, 9)
    for ext in ("", ".meta"):
        assert (tmp_path / f"dask.csv{ext}").read_bytes() == \
            (tmp_path / f"cli.csv{ext}").read_bytes(), ext
    assert table["status"] == ["ok"] * 9
    assert list(table["chain.exponent.base"]) == [2.5] * 3 + [3.0] * 3 + [3.5] * 3
    assert elapsed < 60, f"the cluster sweep took {elapsed:.1f} s"
