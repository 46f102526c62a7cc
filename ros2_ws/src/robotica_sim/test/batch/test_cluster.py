"""Tests of robotica_sim.batch.cluster: a local cluster on loopback, a map over it."""
from pathlib import Path

import psutil
import pytest
from robotica_sim.batch.cluster import dask_client, LOOPBACK, map_on_cluster


def _pid(_: int = 0) -> int:
    import os
    return os.getpid()


def _fails_on_two(x: int) -> int:
    if x == 2:
        raise RuntimeError('two')
    return x * x


def test_a_two_worker_cluster_listens_on_loopback_only_and_is_closed():
    with dask_client(workers=2) as client:
        workers = client.scheduler_info()['workers']
        assert len(workers) == 2
        assert all(address.startswith(f'tcp://{LOOPBACK}:') for address in workers)
        assert all(w['nthreads'] == 1 for w in workers.values())
        pids = set(client.run(_pid).values())
        assert len(pids) == 2
        # Every listening socket of this process's children is on 127.0.0.1.
        me = psutil.Process()
        listening = [c.laddr for p in [me, *me.children(recursive=True)]
                     for c in p.net_connections(kind='inet') if c.status == psutil.CONN_LISTEN]
        assert listening and all(addr.ip == LOOPBACK for addr in listening)
        assert map_on_cluster(client, _pid, [0, 1, 2, 3], list('abcd')) != [None] * 4
    assert not any(psutil.pid_exists(pid) and psutil.Process(pid).status() != 'zombie'
                   for pid in pids)


def test_map_keeps_the_order_and_reports_progress():
    seen = []
    with dask_client(workers=1) as client:
        assert map_on_cluster(client, _fails_on_two, [3, 1], ['x', 'y'],
                              lambda done, r: seen.append((done, r))) == [9, 1]
        with pytest.raises(RuntimeError, match='two'):
            map_on_cluster(client, _fails_on_two, [1, 2], ['p', 'q'])
    assert sorted(seen) == [(1, 1), (2, 9)] or sorted(seen) == [(1, 9), (2, 1)]


def test_bad_worker_count():
    with pytest.raises(ValueError, match='workers must be >= 1'):
        with dask_client(workers=0):
            pass
    assert Path(__file__).is_file()
