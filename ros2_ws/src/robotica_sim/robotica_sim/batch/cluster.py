"""
The Dask cluster of a sweep or a batch grading: local by default, or a running one.

:func:`dask_client` gives a :class:`dask.distributed.Client`. Without an address it starts a
``LocalCluster`` sized to the machine (one worker process per CPU, one thread each: a worker
runs one job at a time, and a run's nodes are processes of their own), and closes it when the
``with`` block ends, also on Ctrl-C. Everything it starts listens on 127.0.0.1 only, on ports
the system chooses (the scheduler, the workers, their nannies and the scheduler's HTTP
endpoint; no dashboard): no traffic leaves the loopback interface. With an address
(``tcp://host:8786``, a ``dask scheduler`` of a course's machines: docs/sweeps.md) it connects
to that cluster and leaves it running.
"""
from contextlib import contextmanager
import os
from typing import Any, Callable, Iterator, Optional, Sequence, TYPE_CHECKING

if TYPE_CHECKING:   # dask.distributed is imported when a cluster is opened (0.5 s)
    from distributed import Client

__all__ = ['LOOPBACK', 'dask_client', 'default_workers', 'map_on_cluster']

LOOPBACK = '127.0.0.1'
"""The host the local cluster's servers bind to."""
CONNECT_TIMEOUT = 30.0   # [s] to reach a scheduler given by address


def default_workers() -> int:
    """Return the number of workers of a local cluster: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:   # not on Linux
        return max(1, os.cpu_count() or 1)


@contextmanager
def dask_client(workers: Optional[int] = None,
                scheduler: Optional[str] = None) -> Iterator['Client']:
    """
    Yield a Dask client: of a new local cluster of ``workers``, or of ``scheduler``'s cluster.

    Parameters
    ----------
    workers : int, optional
        Worker processes of the local cluster (one thread each); default
        :func:`default_workers`. Ignored with ``scheduler`` (the cluster has its own).
    scheduler : str, optional
        Address of a running scheduler (``tcp://10.0.0.5:8786``); None: a local cluster on
        127.0.0.1, closed with the block.

    Raises
    ------
    ValueError
        If ``workers`` is not >= 1.
    OSError
        If the scheduler cannot be reached within 30 s.

    """
    if workers is not None and workers < 1:
        raise ValueError(f'workers must be >= 1, got {workers}')
    from distributed import Client, LocalCluster

    if scheduler is not None:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        try:
            yield client
        finally:
            client.close()
        return
    cluster = LocalCluster(
        n_workers=workers or default_workers(), threads_per_worker=1, processes=True,
        host=LOOPBACK, dashboard_address=f'{LOOPBACK}:0', worker_dashboard_address=None,
        scheduler_kwargs={'dashboard': False})
    try:
        client = Client(cluster)
        try:
            yield client
        finally:
            client.close()
    finally:
        cluster.close()


def map_on_cluster(client: 'Client', function: Callable[[Any], Any], items: Sequence[Any],
                   names: Sequence[str],
                   progress: Optional[Callable[[int, Any], None]] = None) -> list[Any]:
    """
    Return ``[function(item) for item in items]``, computed on the cluster of ``client``.

    Each item is one task named ``names[i]`` (its key on the dashboard), run once (never
    retried: a run is not idempotent). ``progress(done, result)`` is called as each result
    arrives. On Ctrl-C the tasks not yet finished are cancelled and KeyboardInterrupt goes on.
    """
    from distributed import as_completed

    futures = [client.submit(function, item, key=f'{name}-{id(items):x}', pure=False,
                             retries=0) for item, name in zip(items, names)]
    index = {future.key: i for i, future in enumerate(futures)}
    results: list[Any] = [None] * len(futures)
    try:
        for done, future in enumerate(as_completed(futures), start=1):
            results[index[future.key]] = future.result()
            if progress is not None:
                progress(done, results[index[future.key]])
    except BaseException:
        client.cancel(futures, force=True)
        raise
    return results
