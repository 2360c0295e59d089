"""A local Dask cluster shared by the sweep tests (two worker processes on loopback)."""

from __future__ import annotations

import logging

import pytest



@pytest.fixture(scope="session")
def dask_client():
    """Two single-threaded worker processes on 127.0.0.1 (as ``poissonkit sweep`` starts)."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                           dashboard_address="127.0.0.1:0")
    client = Client(cluster)
    yield client
    logging.getLogger("distributed").setLevel(logging.ERROR)  # shutdown chatter
    client.close()
    cluster.close()
